#include "cluster/blas_core.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>

namespace acpca {

namespace {

/// Set in the environment of the program run again, so that its report can
/// say who chose the core.
constexpr const char* kChosenHere = "ACPCA_CHOSE_OPENBLAS_CORETYPE";

}  // namespace

std::string blasCore() {
  // Found at run time: a reference LAPACK has no such function.
  using CoreName = char* (*)();
  static const CoreName name =
      reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  const char* core = name ? name() : nullptr;
  return core ? std::string(core) : std::string("not OpenBLAS");
}

std::string blasCoreChosenBy() {
  if (!std::getenv("OPENBLAS_CORETYPE")) return "OpenBLAS";
  const char* here = std::getenv(kChosenHere);
  return here && std::string(here) == std::getenv("OPENBLAS_CORETYPE") ? "adaptive-cpca"
                                                                       : "OPENBLAS_CORETYPE";
}

std::string cpuBlasCore() {
#if defined(__x86_64__) || defined(__i386__)
  // libgcc's checks include the operating system's support for the registers.
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
      __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
      __builtin_cpu_supports("avx512vl"))
    return "SkylakeX";
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "Haswell";
  if (__builtin_cpu_supports("avx")) return "Sandybridge";
#endif
  return "Prescott";
}

std::string coreTypeToSet(const std::string& detected, const std::string& cpu) {
  return detected == "Prescott" && cpu != "Prescott" ? cpu : std::string();
}

bool blasCoreUnsuited() {
  static const bool unsuited = !coreTypeToSet(blasCore(), cpuBlasCore()).empty();
  return unsuited;
}

void reexecWithSuitedBlasCore(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE")) return;  // the user's choice stands
  const std::string core = coreTypeToSet(blasCore(), cpuBlasCore());
  if (core.empty()) return;
  setenv("OPENBLAS_CORETYPE", core.c_str(), 1);
  setenv(kChosenHere, core.c_str(), 1);
  execv("/proc/self/exe", argv);
  // Not run again (no /proc): OpenBLAS keeps its kernels, Eigen solves instead.
  unsetenv("OPENBLAS_CORETYPE");
  unsetenv(kChosenHere);
}

}  // namespace acpca
