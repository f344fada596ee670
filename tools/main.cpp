// adaptive-cpca: the batch command line (README.md).
#include <algorithm>
#include <iostream>
#include <new>
#include <set>

#include "cluster/blas_core.h"
#include "core/error.h"
#include "core/interrupt_cleanup.h"
#include "core/ranks.h"
#include "core/text.h"
#include "core/version.h"
#include "core/warning.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

/// CLI11 reads an unknown first word as a stray argument ("A subcommand is
/// required"), and with --help prints the main help: name it instead.
void refuseUnknownSubcommand(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return;
  const std::string word = argv[1];
  std::string closest;
  size_t best = SIZE_MAX;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (sub->get_name() == word) return;
    const size_t d = editDistance(word, sub->get_name());
    if (d < best) best = d, closest = sub->get_name();
  }
  throw UserError(concat("unknown subcommand '", word, "'",
                         best <= std::max<size_t>(2, closest.size() / 3)
                             ? concat("; did you mean '", closest, "'?")
                             : std::string(),
                         " (adaptive-cpca --help lists them)"));
}

/// Under `mpirun -np K` with K > 1 only the commands that deal their work over
/// ranks may run; any other would run K times and race for its outputs.
void refuseUndistributedCommand(int argc, char** argv) {
  static const std::set<std::string> spread{"precompute", "build", "relight",
                                            "--help",     "-h",    "--version"};
  if (!ranks::distributed() || argc < 2 || spread.count(argv[1])) return;
  const std::string word = argv[1];
  throw UserError(concat("'", word, "' does not run over MPI ranks (this job has ", ranks::count(),
                         "); only precompute, build and relight do: run ", word,
                         " as one process"));
}

}  // namespace
}  // namespace acpca::cli

int main(int argc, char** argv) {
  // OpenBLAS fell back to kernels that answer wrong on a CPU newer than it:
  // run again with the CPU's own (cluster/blas_core.h), before MPI starts.
  acpca::reexecWithSuitedBlasCore(argv);
  // mpirun -np K: MPI starts here and ends when main returns.
  acpca::ranks::Session mpi(argc, argv);
  // Ctrl-C and SIGTERM remove the unfinished outputs and exit 130 / 143.
  acpca::interrupt::installHandlers();
  // A failing rank ends the whole job: the others may be waiting on it.
  const auto fail = [](int code) { return acpca::ranks::abortAll(code); };
  const std::string rank = acpca::ranks::prefix();
  CLI::App app{"adaptive-cpca: relight fixed-view images under all-frequency environment lighting"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("adaptive-cpca ") + acpca::kVersion);
  acpca::cli::registerPrecompute(app);
  acpca::cli::registerCompress(app);
  acpca::cli::registerBuild(app);
  acpca::cli::registerRelight(app);
  acpca::cli::registerEnvmap(app);
  acpca::cli::registerInfo(app);
  acpca::cli::registerImport(app);
  acpca::cli::registerScenes(app);
  acpca::cli::registerBench(app);
  acpca::cli::registerEval(app);
  acpca::cli::registerAnalyze(app);
  acpca::cli::registerWeb(app);
  acpca::cli::registerView(app);
  // Imperfect input that was accepted (e.g. a map's clamped negative texels).
  acpca::setWarningHandler(
      [](const std::string& text) { std::cerr << "adaptive-cpca: warning: " << text << "\n"; });
  try {
    acpca::cli::refuseUnknownSubcommand(app, argc, argv);
    acpca::cli::refuseUndistributedCommand(argc, argv);
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : fail(code);
  } catch (const acpca::UserError& e) {
    const auto* parameter = dynamic_cast<const acpca::ParameterError*>(&e);
    std::cerr << "adaptive-cpca: " << rank
              << "error: " << (parameter ? acpca::cli::messageWithFlag(*parameter, app) : e.what())
              << "\n";
    return fail(1);
  } catch (const std::bad_alloc&) {
    // Past the estimates (--force, or memory taken by others meanwhile).
    std::cerr << "adaptive-cpca: " << rank
              << "error: out of memory; a smaller image or fewer threads needs less\n";
    return fail(1);
  } catch (const std::exception& e) {
    std::cerr << "adaptive-cpca: " << rank << "internal error: " << e.what() << "\n";
    return fail(3);
  }
  return 0;
}
