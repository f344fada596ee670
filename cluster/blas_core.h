#pragma once
// Which kernels OpenBLAS runs on this CPU, and a better choice where it fell
// back to its generic ones (docs/reliability.md, "When a library answers
// wrong"). OpenBLAS picks its kernels ("core") once, when it loads, from the
// CPU model or from OPENBLAS_CORETYPE. A CPU newer than the OpenBLAS build
// (Debian 12's 0.3.21 on Emerald Rapids or Zen 5) gets its oldest kernels,
// Prescott's, which answered eigenproblems wrong and crashed on such a CPU.
#include <string>

namespace acpca {

/// The core OpenBLAS runs ("Haswell", "SkylakeX", "Prescott", ...), or
/// "not OpenBLAS" when the LAPACK linked is another.
std::string blasCore();

/// Who chose that core: "OpenBLAS" (it detected the CPU), "OPENBLAS_CORETYPE"
/// (the user's environment) or "adaptive-cpca" (reexecWithSuitedBlasCore).
std::string blasCoreChosenBy();

/// What the CPU runs, as OpenBLAS names its cores: "SkylakeX" with AVX-512
/// (F, CD, BW, DQ, VL), "Haswell" with AVX2 and FMA, "Sandybridge" with AVX,
/// else "Prescott".
std::string cpuBlasCore();

/// The OPENBLAS_CORETYPE to set when OpenBLAS runs `detected` on a CPU that
/// runs `cpu`: `cpu` where `detected` is the generic fallback (Prescott) and
/// the CPU has more, else empty (OpenBLAS's choice stands).
std::string coreTypeToSet(const std::string& detected, const std::string& cpu);

/// True while OpenBLAS runs its generic fallback kernels on a CPU that has
/// more (coreTypeToSet would set one): LAPACK is then not asked at all, every
/// eigenproblem goes to Eigen's solver (symmetric_eigen.h).
bool blasCoreUnsuited();

/// For a program's main(), before any thread or MPI starts: when the user set
/// no OPENBLAS_CORETYPE and OpenBLAS fell back to its generic kernels on a CPU
/// that has more, sets OPENBLAS_CORETYPE to the CPU's core and executes the
/// program again (OpenBLAS reads it only as it loads). Returns when there is
/// nothing to do or the exec failed (then every eigenproblem goes to Eigen).
void reexecWithSuitedBlasCore(char** argv);

}  // namespace acpca
