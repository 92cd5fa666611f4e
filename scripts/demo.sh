#!/usr/bin/env bash
# The main job on the built-in default input: installs, builds, then denoises a
# generated noisy table scene with outliers and writes demo_output/demo_input.pcd and
# demo_output/demo_output.pcd.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
mkdir -p demo_output
echo "== running the demo"
./build/examples/pcl_graph_denoise_demo demo_output
