# Sourced by the build scripts: compile through ccache when it is installed
# (scripts/setup.sh installs it). Paths are hashed relative to the checkout, so
# a clone in another folder (CI's) reuses what an earlier build compiled; a
# machine without a cache builds as fast as without ccache.
compiler_cache_flags=()
if command -v ccache >/dev/null 2>&1; then
  export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$(pwd)}"
  export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
  export CCACHE_MAXSIZE="${CCACHE_MAXSIZE:-12G}"
  compiler_cache_flags=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
