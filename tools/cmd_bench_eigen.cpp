// `adaptive-cpca bench eigen`: the global basis's checked eigensolve against
// the same LAPACK solve unchecked (eval/eigen_benchmark.h).
#include "eval/eigen_benchmark.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct EigenBenchArgs {
  CommonOptions common;
  EigenBenchmarkOptions options;
};

}  // namespace

void registerBenchEigen(CLI::App& bench) {
  auto args = std::make_shared<EigenBenchArgs>();
  EigenBenchmarkOptions& o = args->options;
  auto* sub = bench.add_subcommand(
      "eigen", "The global basis's eigensolve: checked against unchecked LAPACK");
  sub->add_option("--size", o.size, "n of the n x n Gram matrix")->capture_default_str();
  sub->add_option("--repeats", o.repeats, "Solves of each kind (the median counts)")
      ->capture_default_str();
  sub->add_flag("--eigen-solver", o.eigenSolver,
                "Also time Eigen's solver, the fallback (slow when large)");
  sub->add_option("--stream-gib", o.streamGiB, "Array size of the streaming-read loop (GiB)")
      ->capture_default_str();
  args->common.add(*sub);
  nameParameters(
      *sub,
      {{"--stream-gib", {"stream size (GiB)"}}, {"--repeats", {"repeats"}}, {"--size", {"size"}}});
  sub->callback([args] { printBenchmark(runEigenBenchmark(args->options), args->common); });
}

}  // namespace acpca::cli
