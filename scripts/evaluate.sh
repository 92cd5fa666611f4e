#!/usr/bin/env bash
# Regenerates the evaluation report: docs/evaluation.md and its pictures. Installs,
# builds, runs build/bench/evaluate section by section (progress on stdout) into a
# results folder, then writes the report from it (scripts/evaluation_report.sh).
#   bash scripts/evaluate.sh [RESULTS_DIR]      (default: a temporary folder)
# Sizes: pugan at 10,000 points (add 50,000 with PGD_PUGAN_SIZES=10000,50000; about
# 25 s per cloud on 2 cores), without WLOP (PGD_WLOP=1 adds it: ~16 s per 10,000 points).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
results=${1:-$(mktemp -d)}
mkdir -p "$results"
wlop=()
[[ "${PGD_WLOP:-0}" == 1 ]] && wlop=(--wlop)
echo "== the paper's Figure 3"
./build/bench/evaluate figure3 --out "$results"
echo "== the PU-GAN protocol"
./build/bench/evaluate pugan --sizes "${PGD_PUGAN_SIZES:-10000}" "${wlop[@]}" --out "$results"
echo "== the raw bunny scans"
./build/bench/evaluate bunny --out "$results"
echo "== outliers"
./build/bench/evaluate outliers --out "$results"
echo "== time-varying clouds"
./build/bench/evaluate sequences --out "$results"
bash scripts/evaluation_report.sh "$results"
