#include "transport/transport_file.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>

#include "core/error.h"
#include "core/half.h"
#include "tests/test_support.h"
#include "transport/file_summary.h"
#include "transport/hdf5_handles.h"

namespace acpca {
namespace {

using test::TempDir;

TransportHeader smallHeader(Precision precision, int rows) {
  TransportHeader h;
  h.camera.size = {8, 4};
  h.cubemapResolution = 2;
  h.precision = precision;
  h.scene = "synthetic";
  h.objectNames = {"floor", "", "plant\nleaf"};  // an empty name, and one holding a line break
  for (int r = 0; r < rows; ++r) {
    h.objects.push_back(r % 3);
    h.pixels.push_back(r * 3 % 32);
    h.albedo.insert(h.albedo.end(), {0.1f * r, 0.5f, 0.25f});
    h.coverage.push_back(1.0f);
    h.normals.insert(h.normals.end(), {0.f, 1.f, 0.f});
    h.positions.insert(h.positions.end(), {0.5f * r, -1.25f, 3.0f - r});
  }
  std::sort(h.pixels.begin(), h.pixels.end());
  return h;
}

std::vector<float> randomRows(int rows, int l) {
  std::mt19937 rng(11);
  std::vector<float> v(static_cast<size_t>(rows) * l);
  for (auto& x : v) x = float(rng() % 10000) / 3000.0f;
  return v;
}

/// A complete transport file of smallHeader(precision, rows) and randomRows.
TransportHeader writeSmallTransport(const std::string& path, Precision precision, int rows) {
  const TransportHeader header = smallHeader(precision, rows);
  TransportWriter writer(path, header);
  const auto values = randomRows(rows, header.latticeSize());
  writer.writeRows(0, rows, values.data());
  writer.finish();
  return header;
}

TEST(Half, RoundTripsWithinHalfAnUlp) {
  std::vector<float> in;
  for (int i = -2000; i < 2000; ++i) in.push_back(i * 0.0137f);
  in.push_back(1e6f);  // clamped to the largest half, never Inf
  std::vector<std::uint16_t> h(in.size());
  std::vector<float> out(in.size());
  floatToHalf(in.data(), h.data(), in.size());
  halfToFloat(h.data(), out.data(), in.size());
  for (size_t i = 0; i + 1 < in.size(); ++i)
    EXPECT_NEAR(out[i], in[i], std::abs(in[i]) * (1.0 / 2048) + 1e-7) << in[i];
  EXPECT_EQ(out.back(), kHalfMax);
}

TEST(Half, ImageConversionRoundsAsIeeeAndOverflowsToInf) {
  // Against Eigen's software half (rounding to nearest even), on values
  // around every half exponent, halfway cases, subnormals and past the range.
  std::vector<float> in;
  std::mt19937 rng(5);
  for (int e = -26; e <= 17; ++e)
    for (int i = 0; i < 200; ++i)
      in.push_back(std::ldexp(1.0f + float(rng() % 4096) / 4096, e) * (i % 2 ? -1.0f : 1.0f));
  in.insert(in.end(), {65504.0f, 65519.0f, 65520.0f, 1e6f, -1e6f, 0.0f, -0.0f,
                       std::numeric_limits<float>::infinity()});
  std::vector<std::uint16_t> out(in.size());
  floatToHalfIeee(in.data(), out.data(), in.size());
  for (size_t i = 0; i < in.size(); ++i)
    ASSERT_EQ(out[i], Eigen::numext::bit_cast<std::uint16_t>(Eigen::half(in[i]))) << in[i];
  EXPECT_EQ(out[in.size() - 5], 0x7c00) << "1e6 is Inf in an image, unlike in our files";
}

TEST(Half, DatasetsReadAsFloatsEqualHdf5sOwnConversion) {
  // Every one of the 65,536 half bit patterns but NaNs, stored as a half
  // dataset; read as floats (the library converts them itself) and as
  // doubles (HDF5's converter): the same numbers, subnormals and Inf included.
  TempDir dir;
  const std::string path = dir.file("halves.h5");
  std::vector<std::uint16_t> all;
  for (std::uint32_t bits = 0; bits < 65536; ++bits)
    if ((bits & 0x7c00) != 0x7c00 || (bits & 0x03ff) == 0) all.push_back(std::uint16_t(bits));
  {
    h5::Handle f = h5::createFile(path, path);
    const h5::Handle half = h5::halfType();
    h5::writeTyped(f.get(), "values", {all.size()}, half.get(), all.data(), path);
    h5::closeWrittenFile(f, path);
  }
  const h5::Handle f = h5::openFileReadOnly(path);
  std::vector<float> floats(all.size());
  std::vector<double> doubles(all.size());
  h5::readDataset(f.get(), "values", floats.data(), path);
  h5::readTyped(f.get(), "values", H5T_NATIVE_DOUBLE, doubles.data(), path);
  for (size_t i = 0; i < all.size(); ++i)
    ASSERT_EQ(floats[i], static_cast<float>(doubles[i])) << "half bits " << all[i];
  EXPECT_EQ(floats[1], std::ldexp(1.0f, -24)) << "the smallest subnormal";
  EXPECT_TRUE(std::isinf(floats[0x7c00]));
}

class TransportRoundTrip : public ::testing::TestWithParam<Precision> {};

TEST_P(TransportRoundTrip, WritesInBlocksAndReadsBack) {
  TempDir dir;
  const std::string path = dir.file("t.h5");
  const TransportHeader header = smallHeader(GetParam(), 10);
  const int l = header.latticeSize();
  const std::vector<float> rows = randomRows(10, l);
  {
    TransportWriter writer(path, header);
    writer.writeRows(0, 3, rows.data());
    writer.writeRows(3, 7, rows.data() + 3 * l);
    EXPECT_FALSE(test::fs::exists(path)) << "visible before finish()";
    writer.finish();
  }
  const TransportReader reader(path);
  EXPECT_EQ(reader.rows(), 10);
  EXPECT_EQ(reader.header().pixels, header.pixels);
  EXPECT_EQ(reader.header().albedo, header.albedo);
  EXPECT_EQ(reader.header().positions, header.positions);
  EXPECT_TRUE(reader.header().hasPositions());
  EXPECT_EQ(reader.header().normals, header.normals);
  EXPECT_EQ(reader.header().objects, header.objects);
  EXPECT_EQ(reader.header().objectNames,
            (std::vector<std::string>{"floor", "", "plant leaf"}));  // a name is one line
  EXPECT_EQ(reader.header().scene, "synthetic");
  EXPECT_EQ(reader.header().camera.size.width, 8);
  std::vector<float> back(rows.size());
  reader.readRows(0, 10, back.data());
  const double tolerance = GetParam() == Precision::F16 ? 1.0 / 2048 : 0;
  for (size_t i = 0; i < rows.size(); ++i)
    ASSERT_NEAR(back[i], rows[i], std::abs(rows[i]) * tolerance) << i;
  std::vector<float> middle(2 * l);
  reader.readRows(4, 2, middle.data());
  EXPECT_EQ(std::vector<float>(back.begin() + 4 * l, back.begin() + 6 * l), middle);
}

INSTANTIATE_TEST_SUITE_P(Precisions, TransportRoundTrip,
                         ::testing::Values(Precision::F16, Precision::F32));

TEST(TransportFile, AnUnfinishedWriterLeavesNoFile) {
  TempDir dir;
  const std::string path = dir.file("t.h5");
  {
    TransportWriter writer(path, smallHeader(Precision::F16, 4));
    const auto rows = randomRows(2, 24);
    writer.writeRows(0, 2, rows.data());
  }  // destroyed without finish(), as when a precompute fails half-way
  EXPECT_FALSE(test::fs::exists(path));
  EXPECT_TRUE(test::fs::is_empty(dir.path())) << "temporary file left behind";
}

TEST(TransportFile, RefusesMissingForeignAndTruncatedFiles) {
  TempDir dir;
  EXPECT_THROW(TransportReader(dir.file("missing.h5")), UserError);
  { std::ofstream(dir.file("foreign.h5")) << "this is not an HDF5 file"; }
  EXPECT_THROW(TransportReader(dir.file("foreign.h5")), UserError);

  const std::string path = dir.file("t.h5");
  const TransportHeader header = writeSmallTransport(path, Precision::F32, 10);
  const auto size = test::fs::file_size(path);
  for (double keep : {0.3, 0.6, 0.9}) {
    const std::string cut = dir.file("cut.h5");
    test::fs::copy_file(path, cut, test::fs::copy_options::overwrite_existing);
    test::fs::resize_file(cut, static_cast<uintmax_t>(size * keep));
    try {
      const TransportReader reader(cut);
      std::vector<float> rows(10 * header.latticeSize());
      reader.readRows(0, 10, rows.data());
      FAIL() << "a file cut to " << keep << " of its size was read";
    } catch (const UserError& e) {
      EXPECT_NE(std::string(e.what()).find("cut.h5"), std::string::npos) << e.what();
    }
  }
}

// Found by fuzz_model_file: libhdf5 read freed memory while parsing a damaged
// object header. Files are now written in the 1.10 format, whose metadata is
// checksummed, so damage is refused before HDF5 parses it. Every damaged byte
// must give a UserError or rows that read back finite (ASan checks the rest).
TEST(TransportFile, DamagedBytesAreRefusedOrReadBackFinite) {
  TempDir dir;
  const std::string path = dir.file("t.h5");
  writeSmallTransport(path, Precision::F16, 6);
  std::ifstream in(path, std::ios::binary);
  const std::string original((std::istreambuf_iterator<char>(in)), {});
  int refused = 0, read = 0;
  // About 400 positions spread over the file (metadata and rows alike).
  const size_t stride = std::max<size_t>(1, original.size() / 400) | 1;
  for (size_t at = 0; at < original.size(); at += stride) {
    std::string damaged = original;
    damaged[at] = static_cast<char>(damaged[at] ^ 0x5A);
    const std::string bad = dir.file("bad.h5");
    std::ofstream(bad, std::ios::binary | std::ios::trunc) << damaged;
    try {
      const TransportReader reader(bad);
      std::vector<float> rows(reader.rows() * reader.latticeSize());
      reader.readRows(0, reader.rows(), rows.data());
      for (float v : rows) ASSERT_TRUE(std::isfinite(v)) << "byte " << at;
      ++read;
    } catch (const UserError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 0);
  EXPECT_GT(read, 0);  // damage to row values alone is not detectable
}

TEST(TransportFile, FilesWithoutMetadataChecksumsAreRefusedByName) {
  TempDir dir;
  const std::string path = dir.file("old.h5");
  H5Fclose(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT));  // superblock 0
  try {
    TransportReader reader(path);
    FAIL() << "an unchecksummed file was opened";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("without metadata checksums"), std::string::npos)
        << e.what();
  }
}

// Found by fuzz_hdf5_headers: datasets declared with dimensions the file does
// not hold (a 16384^2 image, every per-pixel array declared but never written)
// are refused before anything is allocated for them.
TEST(TransportFile, AbsurdDeclaredShapesAreRefusedBeforeAllocation) {
  TempDir dir;
  const std::string path = dir.file("t.h5");
  writeSmallTransport(path, Precision::F32, 2);
  {
    h5::Handle f(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
    const long long side = 16384, n = side * side;
    for (const char* a : {"width", "height", "occupied_pixels"}) {
      H5Adelete(f.get(), a);
      h5::writeAttribute(f.get(), a, a[0] == 'o' ? n : side, path);
    }
    for (auto [name, columns] : {std::pair{"pixels", 0},
                                 {"albedo", 3},
                                 {"coverage", 0},
                                 {"normal", 3},
                                 {"transport", 24}}) {
      H5Ldelete(f.get(), name, H5P_DEFAULT);
      hsize_t dims[2] = {hsize_t(n), hsize_t(columns)}, chunk[2] = {1024, 1};
      h5::Handle space(H5Screate_simple(columns ? 2 : 1, dims, nullptr), H5Sclose);
      h5::Handle create(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
      H5Pset_chunk(create.get(), columns ? 2 : 1, chunk);
      h5::Handle set(H5Dcreate2(f.get(), name, name[0] == 'p' ? H5T_NATIVE_INT32 : H5T_NATIVE_FLOAT,
                                space.get(), H5P_DEFAULT, create.get(), H5P_DEFAULT),
                     H5Dclose);
      ASSERT_GE(set.get(), 0) << name;
    }
  }
  try {
    TransportReader reader(path);
    FAIL() << "a header declaring 2^28 rows that the file does not hold was accepted";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("declares"), std::string::npos) << e.what();
  }
}

TEST(TransportFile, HeaderValidationNamesTheProblem) {
  TransportHeader h = smallHeader(Precision::F16, 3);
  h.albedo.pop_back();
  EXPECT_THROW(h.validate("x"), UserError);
  h = smallHeader(Precision::F16, 3);
  std::swap(h.pixels[0], h.pixels[1]);
  EXPECT_THROW(h.validate("x"), UserError);
  h = smallHeader(Precision::F16, 3);
  h.camera.size = {0, 4};
  EXPECT_THROW(h.validate("x"), UserError);
  h = smallHeader(Precision::F16, 3);
  h.albedo[0] = NAN;
  EXPECT_THROW(h.validate("x"), UserError);
  h = smallHeader(Precision::F16, 3);
  h.positions[4] = INFINITY;
  EXPECT_THROW(h.validate("x"), UserError);
  h = smallHeader(Precision::F16, 3);
  h.positions.pop_back();
  EXPECT_THROW(h.validate("x"), UserError);
  h = smallHeader(Precision::F16, 3);
  h.objects[1] = 3;  // one past the names
  EXPECT_THROW(h.validate("x"), UserError);
  h = smallHeader(Precision::F16, 3);
  h.objects.pop_back();
  EXPECT_THROW(h.validate("x"), UserError);
}

/// Turns a file written now into one as an earlier version wrote it: without
/// objects (version 2), and without positions either (version 1).
void makeOlderFile(const std::string& path, long long version) {
  h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  ASSERT_GE(file.get(), 0);
  ASSERT_GE(H5Ldelete(file.get(), "object", H5P_DEFAULT), 0);
  ASSERT_GE(H5Adelete(file.get(), "object_names"), 0);
  if (version < 2) {
    ASSERT_GE(H5Ldelete(file.get(), "position", H5P_DEFAULT), 0);
  }
  ASSERT_GE(H5Adelete(file.get(), "version"), 0);
  h5::writeAttribute(file.get(), "version", version, path);
}

TEST(TransportFile, EarlierVersionsAreReadWithoutWhatTheyLacked) {
  for (long long version : {1, 2}) {
    TempDir dir;
    const std::string path = dir.file("old.h5");
    const TransportHeader written = writeSmallTransport(path, Precision::F16, 5);
    makeOlderFile(path, version);
    const TransportReader reader(path);
    EXPECT_FALSE(reader.header().hasObjects());
    EXPECT_EQ(reader.header().hasPositions(), version == 2);
    EXPECT_EQ(reader.header().albedo, written.albedo);
    EXPECT_EQ(reader.header().normals, written.normals);
    std::vector<float> rows(5 * reader.rowLength());
    reader.readRows(0, 5, rows.data());  // the rows are as readable as before
  }
}

TEST(TransportFile, ASummaryIsTheHeaderWithoutReadingItsArraysAtAnyVersion) {
  for (long long version : {1, 2, 4}) {
    TempDir dir;
    const std::string path = dir.file("t.h5");
    writeSmallTransport(path, Precision::F32, 5);
    if (version < 4) makeOlderFile(path, version);
    TransportHeader whole;
    long long bytes = 0;
    {  // closed again before the file is opened for writing below
      const TransportReader reader(path);
      whole = reader.header();
      bytes = reader.fileBytes();
    }
    const auto expectSame = [&](const TransportSummary& s) {
      EXPECT_EQ(s.pixels.rows, whole.rows());
      EXPECT_EQ(s.pixels.normals, whole.hasNormals());
      EXPECT_EQ(s.pixels.positions, whole.hasPositions());
      EXPECT_EQ(s.pixels.objects, whole.hasObjects());
      EXPECT_EQ(s.header.objectNames, whole.objectNames);
      EXPECT_EQ(s.header.precision, whole.precision);
      EXPECT_EQ(s.header.rowLength(), whole.rowLength());
      EXPECT_TRUE(s.header.pixels.empty() && s.header.albedo.empty());  // never read
      EXPECT_EQ(s.fileBytes, bytes);
    };
    expectSame(readTransportSummary(path));
    // Spoilt per-pixel values: the reader refuses the file, the summary is unmoved.
    {
      h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
      h5::Handle normal(H5Dopen2(file.get(), "normal", H5P_DEFAULT), H5Dclose);
      const std::vector<float> nan(15, std::numeric_limits<float>::quiet_NaN());
      ASSERT_GE(H5Dwrite(normal.get(), H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, nan.data()),
                0);
    }
    EXPECT_THROW(TransportReader{path}, UserError);
    expectSame(readTransportSummary(path));
  }
}

TEST(TransportFile, VersionsOutsideTheReadRangeAreRefusedByNumber) {
  TempDir dir;
  const std::string path = dir.file("v9.h5");
  writeSmallTransport(path, Precision::F16, 2);
  {
    h5::Handle file(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
    ASSERT_GE(H5Adelete(file.get(), "version"), 0);
    h5::writeAttribute(file.get(), "version", 9LL, path);
  }
  try {
    TransportReader reader(path);
    FAIL() << "version 9 was read";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("version 9"), std::string::npos) << e.what();
  }
}

TEST(TransportFile, RefusesAnUnwritableDestination) {
  TempDir dir;
  EXPECT_THROW(TransportWriter(dir.file("no/such/dir/t.h5"), smallHeader(Precision::F16, 2)),
               UserError);
}

}  // namespace
}  // namespace acpca
