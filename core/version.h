#pragma once
// The project's version, written once: project(... VERSION ...) in the top
// CMakeLists.txt. The CLI's --version and Python's adaptive_cpca.__version__
// read it from here.

namespace acpca {

inline constexpr const char* kVersion = ACPCA_VERSION;

}  // namespace acpca
