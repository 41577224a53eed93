#!/bin/sh
# The installed package as a host program sees it: installs the build tree BUILD into
# WORK/prefix, builds tests/consumer against it with find_package(dacrt), renders the Cornell box
# with the installed CLI and with the consumer, and has the consumer compare the two.
#   consumer_check.sh BUILD SOURCE WORK [CXXFLAGS]
set -eu
build=$1 source=$2 work=$3 flags=${4:-}
rm -rf "$work"
mkdir -p "$work"

# Runs a step with its output in WORK/NAME.log, shown when the step fails.
step() {
  name=$1
  shift
  if ! "$@" > "$work/$name.log" 2>&1; then
    echo "consumer check: $name failed: $*"
    cat "$work/$name.log"
    exit 1
  fi
}

step install cmake --install "$build" --prefix "$work/prefix"
step configure cmake -S "$source/tests/consumer" -B "$work/build" \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="$flags"
step build cmake --build "$work/build"
scene="$source/scenes/cornell-box.gltf"
step render "$work/prefix/bin/dacrt" render "$scene" --width 24 --height 16 --spp 4 --seed 7 \
  --quiet -o "$work/cli.exr"
"$work/build/consumer" "$scene" "$work/cli.exr" 24 16 4 7

# The installed Python module, when the build has one: imported from the prefix alone.
# The package is the folder dacrt/ (its Python files and the native _dacrt module).
module=$(find "$work/prefix" -name '_dacrt.cpython-*.so' | head -n 1)
if [ -n "$module" ]; then
  python=${DACRT_PYTHON:-/usr/bin/python3}
  # Installed to /usr/local, the package would be where the interpreter looks without PYTHONPATH.
  where=$(dirname "$(dirname "$module")")
  where=/usr/local/${where#"$work/prefix/"}
  if ! "$python" -c "import sys; sys.exit('$where' not in sys.path)"; then
    echo "consumer check: the module installs to PREFIX/${where#/usr/local/}, which $python does not search under /usr/local"
    exit 1
  fi
  preload=""
  case "$flags" in  # a sanitized module needs the sanitizers' runtime (and libstdc++, for
    # ASan's __cxa_throw interceptor) loaded before the interpreter
    *sanitize=address*) preload="$(c++ -print-file-name=libasan.so):$(c++ -print-file-name=libstdc++.so)" ;;
  esac
  LD_PRELOAD=$preload ASAN_OPTIONS=detect_leaks=0 PYTHONPATH=$(dirname "$(dirname "$module")") "$python" -c "
import sys, dacrt
assert dacrt.__file__.startswith('$work/prefix'), dacrt.__file__
image = dacrt.read_exr('$work/cli.exr')
mine = dacrt.render('$scene', width=24, height=16, spp=4, seed=7)
assert (mine[..., 0] == image['R']).all(), 'the installed module renders otherwise'
print('consumer: the installed Python module renders as the CLI does')
"
fi
