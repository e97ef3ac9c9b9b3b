#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs, only those missing. Idempotent; uses sudo when
# not root. Called by `make deps` (and so by `make demo` and `make test`).
set -euo pipefail

# The list: scripts/packages.txt (one package a line, '#' comments), checked complete by
# tests/setup/test_setup_complete.py.
packages=()
while read -r line; do
  line="${line%%#*}"
  for p in $line; do packages+=("$p"); done
done < "$(dirname "$0")/packages.txt"

# Optional extras (e.g. the benchmark's reference libraries), space separated.
read -r -a extra <<< "${ST_EXTRA_PACKAGES:-}"
packages+=("${extra[@]}")

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
