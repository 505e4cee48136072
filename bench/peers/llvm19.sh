# Sourced by run.sh and scramble.sh: Mitsuba's llvm_ad_rgb needs LLVM 19 (it refuses LLVM 14
# and crashes with 15). Installs Debian's libllvm19 when missing and exports
# DRJIT_LIBLLVM_PATH, the library Dr.Jit loads.
llvm="$(ls /usr/lib/x86_64-linux-gnu/libLLVM.so.19* /usr/lib/llvm-19/lib/libLLVM.so* 2>/dev/null | head -n1 || true)"
if [ -z "$llvm" ]; then
  echo "Mitsuba's llvm_ad_rgb needs LLVM 19: installing Debian's libllvm19" >&2
  if [ "$(id -u)" = 0 ]; then apt-get install -y libllvm19 >&2; else sudo apt-get install -y libllvm19 >&2; fi
  # Debian puts it in one of the two places: `ls` fails on the other (and `set -e` would stop).
  llvm="$(ls /usr/lib/x86_64-linux-gnu/libLLVM.so.19* /usr/lib/llvm-19/lib/libLLVM.so* 2>/dev/null | head -n1 || true)"
  [ -n "$llvm" ] || { echo "libllvm19 installed, but no libLLVM.so.19 found" >&2; exit 1; }
fi
export DRJIT_LIBLLVM_PATH="$llvm"
