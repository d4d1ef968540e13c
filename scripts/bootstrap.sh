#!/usr/bin/env bash
# Installs what a fresh machine lacks for lorentz-gas, and nothing else:
#   GNU m4 and a C compiler, which rug's bundled GMP/MPFR build needs (Debian/Ubuntu: apt-get).
# The system's GMP and MPFR (libgmp-dev, libmpfr-dev) are not needed: the build links rug's own,
# built once and cached (docs/performance.md, "Building GMP and MPFR", says why).
# Safe to run any number of times: it only installs what is missing.
set -euo pipefail

missing=()
command -v m4 >/dev/null 2>&1 || missing+=(m4)
command -v cc >/dev/null 2>&1 || missing+=(gcc)
command -v make >/dev/null 2>&1 || missing+=(make)

if ((${#missing[@]})); then
  if ! command -v apt-get >/dev/null 2>&1; then
    echo "bootstrap: please install ${missing[*]} with your package manager (needed by rug's GMP/MPFR build)" >&2
    exit 1
  fi
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null 2>&1 || { echo "bootstrap: run as root or install sudo to install ${missing[*]}" >&2; exit 1; }
    SUDO="sudo"
  fi
  echo "bootstrap: installing ${missing[*]} (needed by rug's bundled GMP/MPFR build)" >&2
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

command -v cargo >/dev/null 2>&1 || {
  echo "bootstrap: cargo not found: install stable Rust (1.89 or newer, the rust-version of Cargo.toml) with rustup" >&2
  exit 1
}
echo "bootstrap: m4, a C compiler and cargo are present" >&2
