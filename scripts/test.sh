#!/usr/bin/env bash
# Installs, builds and runs the whole test suite (GoogleTest through CTest).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
echo "== running the tests"
cd build
ctest --output-on-failure --parallel 2
