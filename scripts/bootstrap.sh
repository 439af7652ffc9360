#!/usr/bin/env bash
# Installs what building modia3d needs and is not part of a Rust toolchain (cmake for the vendored
# SUNDIALS, libclang for bindgen), then runs the given command with the environment set.
#
#   scripts/bootstrap.sh                      # only install / check
#   scripts/bootstrap.sh cargo test --workspace
#
# Does nothing when cmake and libclang are already there. As root on Debian it uses apt-get;
# otherwise it makes a Python venv with the PyPI `cmake` and `libclang` wheels and points
# CMAKE, LIBCLANG_PATH and BINDGEN_EXTRA_CLANG_ARGS at them. MODIA3D_BOOTSTRAP=pip forces the
# venv route (to test it, or where apt-get must not be used).
set -euo pipefail

log() { printf 'bootstrap: %s\n' "$*" >&2; }

have_cmake() {
  if [ -n "${CMAKE:-}" ] && [ -x "${CMAKE}" ]; then return 0; fi
  command -v cmake >/dev/null 2>&1
}

find_libclang() {
  # Prints the directory that holds a libclang shared object, or nothing.
  local d f
  if [ -n "${LIBCLANG_PATH:-}" ]; then
    for f in "${LIBCLANG_PATH}"/libclang*.so*; do [ -e "$f" ] && { echo "${LIBCLANG_PATH}"; return; }; done
  fi
  for d in /usr/lib/llvm-*/lib /usr/lib/x86_64-linux-gnu /usr/lib/aarch64-linux-gnu /usr/lib64 /usr/lib /usr/local/lib; do
    for f in "$d"/libclang.so* "$d"/libclang-*.so*; do
      [ -e "$f" ] && { echo "$d"; return; }
    done
  done
}

# clang's own headers (stddef.h, …) must be found by bindgen; libclang-common-*-dev ships them.
have_clang_headers() {
  compgen -G "/usr/lib/llvm-*/lib/clang/*/include/stddef.h" >/dev/null 2>&1 ||
    [ -n "${BINDGEN_EXTRA_CLANG_ARGS:-}" ]
}

install_with_apt() {
  export DEBIAN_FRONTEND=noninteractive
  local pkgs="cmake libclang1-14 libclang-common-14-dev"
  log "installing $pkgs with apt-get"
  if ! apt-get install -y -qq --no-install-recommends $pkgs >/dev/null 2>&1; then
    apt-get update -qq >/dev/null 2>&1 || true
    if ! apt-get install -y -qq --no-install-recommends $pkgs >/dev/null 2>&1; then
      log "libclang 14 not available; falling back to libclang-dev"
      apt-get install -y -qq --no-install-recommends cmake libclang-dev >/dev/null
    fi
  fi
}

install_with_pip() {
  local venv="${XDG_CACHE_HOME:-$HOME/.cache}/modia3d-bootstrap/venv"
  if [ ! -x "$venv/bin/cmake" ] || ! compgen -G "$venv/lib/python*/site-packages/clang/native/libclang*.so*" >/dev/null; then
    log "no root: installing cmake and libclang wheels into $venv"
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q cmake libclang
  fi
  export CMAKE="$venv/bin/cmake"
  export PATH="$venv/bin:$PATH"
  LIBCLANG_PATH="$(dirname "$(compgen -G "$venv/lib/python*/site-packages/clang/native/libclang*.so*" | head -n1)")"
  export LIBCLANG_PATH
  export BINDGEN_EXTRA_CLANG_ARGS="-I$(gcc -print-file-name=include)"
}

if [ "${MODIA3D_BOOTSTRAP:-}" = pip ]; then
  install_with_pip
elif have_cmake && [ -n "$(find_libclang)" ] && have_clang_headers; then
  :
elif [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
  install_with_apt
else
  install_with_pip
fi

if [ -z "${LIBCLANG_PATH:-}" ]; then
  LIBCLANG_PATH="$(find_libclang)"
  [ -n "$LIBCLANG_PATH" ] && export LIBCLANG_PATH
fi
have_cmake || { log "cmake is still missing"; exit 1; }
[ -n "${LIBCLANG_PATH:-}" ] || { log "libclang is still missing"; exit 1; }

if [ "$#" -gt 0 ]; then
  exec "$@"
fi
