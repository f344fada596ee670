// Start-up without what a command does not use: OpenImageIO and Qt live in
// plugins loaded on first use (docs/architecture.md, "Plugins"). Commands
// that touch no image run with the plugins unreachable; the first image of
// one that does names the plugin it could not load and writes nothing; and
// `info` reads a file's attributes and shapes alone.
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/cli/run_cli.h"
#include "tests/test_support.h"
#include "transport/hdf5_handles.h"

namespace acpca {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

/// The environment that puts both plugins out of reach.
const std::string kNoPlugins =
    "ACPCA_IMAGE_CODECS=/nonexistent/libacpca_image_codecs.so "
    "ACPCA_WINDOW=/nonexistent/libacpca_window.so";

TEST(Startup, TheCliLinksNeitherOpenImageIoNorQt) {
  // The dynamic loader lists what the executable pulls in before main().
  const RunResult r = runShell("LD_TRACE_LOADED_OBJECTS=1 " + std::string(ACPCA_CLI_PATH));
  ASSERT_EQ(r.status, 0) << r.output;
  ASSERT_NE(r.output.find("libhdf5"), std::string::npos) << r.output;  // the listing is real
  for (const char* heavy : {"libOpenImageIO", "libQt5", "libopencv_highgui", "libgdcm"})
    EXPECT_EQ(r.output.find(heavy), std::string::npos) << heavy << " loads at start-up";
}

TEST(Startup, CommandsWithoutImagesNeverLoadAPlugin) {
  TempDir dir;
  const std::string model = dir.file("m.h5");
  ASSERT_EQ(runCli("compress " + test::fixture("small-plant") +
                       " --method adaptive-quad --quiet --out " + model,
                   kNoPlugins)
                .status,
            0);
  for (const std::string& args :
       {std::string("--version"), std::string("--help"), std::string("scenes"), "info " + model,
        "info " + test::fixture("small-plant") + " --json -"}) {
    const RunResult r = runCli(args, kNoPlugins);
    EXPECT_EQ(r.status, 0) << args << "\n" << r.output;
    EXPECT_EQ(r.output.find("cannot load"), std::string::npos) << args << "\n" << r.output;
  }
}

TEST(Startup, AMissingOrBrokenPluginIsNamedAtTheFirstImageAndNothingIsWritten) {
  TempDir dir;
  const std::string notALibrary = dir.file("libacpca_image_codecs.so");
  test::writeFile(notALibrary, "not a shared object");
  // A map to read through the plugin: Radiance HDR (EXR maps are read, and
  // EXR and PNG frames written, without it, by imageio's own code).
  const std::string map = dir.file("map.hdr"), exrMap = dir.file("map.exr");
  ASSERT_EQ(runCli("envmap sky --size 32x16 --quiet --out " + map).status, 0);
  ASSERT_EQ(runCli("envmap sky --size 32x16 --quiet --out " + exrMap).status, 0);
  const struct {
    std::string plugin, says;
  } cases[] = {
      {"/nonexistent/libacpca_image_codecs.so", "/nonexistent/libacpca_image_codecs.so: not there"},
      {notALibrary, notALibrary + ": "},
      // A real shared object that is not the codecs.
      {ACPCA_WINDOW_PLUGIN, "exports no acpca_image_codecs"}};
  for (const auto& c : cases) {
    const std::string out = dir.file("frame.exr");
    const RunResult r = runCli(
        "relight " + test::fixture("small-plant") + " --env " + map + " --quiet --out " + out,
        "ACPCA_IMAGE_CODECS=" + c.plugin);
    EXPECT_EQ(r.status, 1) << r.output;
    EXPECT_NE(r.output.find("cannot load the image codecs"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(c.says), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
    for (const auto& e : fs::directory_iterator(dir.path()))
      EXPECT_EQ(e.path().filename().string().find(".frame"), std::string::npos)
          << e.path() << " left behind";
    // An EXR map needs no plugin, nor do EXR and PNG frames.
    for (const char* name : {"lit.exr", "lit.png"}) {
      const RunResult sky = runCli("relight " + test::fixture("small-plant") + " --env " + exrMap +
                                       " --quiet --out " + dir.file(name),
                                   "ACPCA_IMAGE_CODECS=" + c.plugin);
      EXPECT_EQ(sky.status, 0) << sky.output;
      EXPECT_GT(fs::file_size(dir.file(name)), 100u);
    }
  }
  // The same command with the codecs in reach writes its image.
  ASSERT_EQ(runCli("relight " + test::fixture("small-plant") + " --env " + map + " --quiet --out " +
                   dir.file("frame.exr"))
                .status,
            0);
  EXPECT_GT(fs::file_size(dir.file("frame.exr")), 100u);
}

TEST(Startup, InfoOfAModelReadsNeitherItsCoefficientsNorItsPixels) {
  TempDir dir;
  const std::string model = dir.file("m.h5");
  ASSERT_EQ(runCli("compress " + test::fixture("small-plant") +
                   " --method adaptive-quad --quiet --out " + model)
                .status,
            0);
  const RunResult before = runCli("info " + model + " --json -");
  ASSERT_EQ(before.status, 0) << before.output;
  {  // NaN over every coefficient and albedo: a relight must refuse the file
    h5::Handle file(H5Fopen(model.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
    for (const char* name : {"coefficients", "albedo"}) {
      h5::Handle data(H5Dopen2(file.get(), name, H5P_DEFAULT), H5Dclose);
      h5::Handle space(H5Dget_space(data.get()), H5Sclose);
      const std::vector<float> nan(static_cast<size_t>(H5Sget_simple_extent_npoints(space.get())),
                                   std::numeric_limits<float>::quiet_NaN());
      ASSERT_GE(H5Dwrite(data.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, nan.data()),
                0);
    }
  }
  const RunResult relit =
      runCli("relight " + model + " --env sky --quiet --out " + dir.file("a.exr"));
  EXPECT_EQ(relit.status, 1) << relit.output;
  // info reports what it reported before, byte for byte: it never read them.
  const RunResult after = runCli("info " + model + " --json -");
  EXPECT_EQ(after.status, 0) << after.output;
  EXPECT_EQ(nlohmann::json::parse(after.output), nlohmann::json::parse(before.output));
}

}  // namespace
}  // namespace acpca
