// `adaptive-cpca bench codecs`: a frame in each batch format, imageio's
// encoders against OpenImageIO's writer (eval/codec_benchmark.h).
#include <filesystem>

#include "eval/codec_benchmark.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct CodecBenchArgs {
  CommonOptions common;
  CodecBenchmarkOptions options;
};

}  // namespace

void registerBenchCodecs(CLI::App& bench) {
  auto args = std::make_shared<CodecBenchArgs>();
  CodecBenchmarkOptions& o = args->options;
  auto* sub = bench.add_subcommand(
      "codecs", "A frame in each batch format: imageio's encoders vs OpenImageIO's writer");
  sub->add_option("image", o.image, "A frame to encode (an EXR a batch wrote, say)")->required();
  sub->add_option("--dir", o.directory, "Directory the files are written to and removed from")
      ->capture_default_str();
  sub->add_option("--repeats", o.repeats, "Encodings of each case (the median counts)")
      ->capture_default_str();
  sub->add_option("--stream-gib", o.streamGiB, "Array size of the streaming-read loop (GiB)")
      ->capture_default_str();
  args->common.add(*sub);
  nameParameters(*sub, {{"--stream-gib", {"stream size (GiB)"}}, {"--repeats", {"repeats"}}});
  sub->callback([args] {
    if (args->options.directory.empty())
      args->options.directory = std::filesystem::temp_directory_path().string();
    printBenchmark(runCodecBenchmark(args->options), args->common);
  });
}

}  // namespace acpca::cli
