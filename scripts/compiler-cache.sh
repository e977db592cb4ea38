# Sourced by the scripts that configure a build: compiles through ccache when it is installed, so
# that a fresh checkout (CI builds one three times) reuses what an earlier checkout compiled.
# Sets `launcher`, the CMake flag to pass, empty without ccache.
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  # Paths inside the checkout are hashed relative to it, and the sanitizer build's -g1 objects
  # without their build directory, so that checkouts in other places hit.
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=true
  # CMake's precompiled headers are generated during the build: without this ccache would
  # compile every file that includes one.
  export CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime
fi
