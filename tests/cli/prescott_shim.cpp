// LD_PRELOADed by tests/cli/blas_core_test.cpp: OpenBLAS's answer on a CPU it
// does not know (its generic Prescott kernels) while OPENBLAS_CORETYPE is
// unset; the real OpenBLAS's once it is set.
#include <dlfcn.h>

#include <cstdlib>

extern "C" char* openblas_get_corename() {
  static char prescott[] = "Prescott";
  if (!std::getenv("OPENBLAS_CORETYPE")) return prescott;
  using CoreName = char* (*)();
  const auto real = reinterpret_cast<CoreName>(dlsym(RTLD_NEXT, "openblas_get_corename"));
  return real ? real() : prescott;
}
