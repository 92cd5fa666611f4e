#!/usr/bin/env bash
# Writes docs/evaluation.md and its pictures from the results folder that
# build/bench/evaluate filled (see scripts/evaluate.sh): plots with gnuplot, renders
# with build/bench/render_views under Xvfb.
#   bash scripts/evaluation_report.sh RESULTS_DIR
set -euo pipefail
cd "$(dirname "$0")/.."
results=$1
for tool in gnuplot xvfb-run; do
  if ! command -v $tool >/dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
      gnuplot-nox xvfb xauth >/dev/null
  fi
done
gnuplot -e "data='$results/figure3.dat'; out='docs/figure3.png'" docs/figure3.gp
xvfb-run -a -s "-screen 0 1920x1080x24" ./build/bench/render_views docs/bunny_bun000.png \
  --size 2400 800 --range 0 0.3 --view 0 0 -1 0 1 0 --scalar-title "distance to the reconstruction (mm)" \
  "raw scan bun000" "$results/bunny_bun000_noisy.pcd" \
  "GraphTVSmoothing, defaults" "$results/bunny_bun000_TV.pcd" \
  "MLS, best radius" "$results/bunny_bun000_MLS.pcd"
{
  cat <<'HEAD'
# Evaluation

Regenerate everything on this page with `bash scripts/evaluate.sh` (it installs, builds, runs
`build/bench/evaluate` section by section and writes this page with
`scripts/evaluation_report.sh`). Seeds are fixed: the numbers are reproducible (the times are
not: they are wall-clock seconds on the machine that ran it, 2 cores).

Since the PU-GAN numbers below, the smoothers apply two refinements beyond the paper by default
(`setNormalDisplacement`, `setShrinkageCorrection`, see section 4); turning both off gives the
paper's filters exactly.

## 1. The paper's experiment (its Figure 3)

A square plane [-1,1]², the unit sphere and the cube [-1,1]³, each sampled uniformly at random
10,000 times; Gaussian noise of standard deviation σ at nine levels from 0.001 to 0.1, spaced
logarithmically; the mean distance of the points to the true surface (exact) for the noisy input,
`GraphTikhonovSmoothing` and `GraphTVSmoothing` with default parameters (k = 10, θ and γ derived
from the data), and each at the best γ of a sweep over 1/16× to 16× its default. Command:
`build/bench/evaluate figure3`.

![Figure 3](figure3.png)

HEAD
  cat "$results/figure3.md"
  cat <<'MID'

## 2. The standard benchmark: the PU-GAN meshes with the score-based denoising protocol

Protocol of Luo & Hu 2021 (ScoreDenoise) as its code computes it: each mesh of
`../shared/data/meshes/pugan_test` (16 meshes) normalised to the unit sphere (centre of the
bounding box of its vertices, largest radius 1); points sampled uniformly at random on its
triangles; Gaussian noise σ = 1%, 2%, 3%. **CD** (×10⁴): mean squared distance from each
result point to the nearest clean point plus the same the other way (both clouds normalised by the
clean cloud's bounding box and radius). **P2M** (×10⁴): mean squared distance of the result
points to the mesh plus the mean over the triangles of the squared distance to the nearest result
point. Each cell: the mean over the meshes, `CD / P2M`, lower is better. Ours: defaults, and at
the best γ of 1/4×–4× the default. The peers are given the best setting of a sweep **per cloud**
(chosen by P2M against the true mesh, which a user cannot do): `pcl::MovingLeastSquares` (order
2, radius 1–3× the mean distance to the 20th neighbour), CGAL `jet_smooth_point_set` (k = 18,
36, 72), CGAL `bilateral_smooth_point_set` (3 passes, sharpness 25°, k = 30, 60, 120, on
normals from `jet_estimate_normals` oriented by `mst_orient_normals`). CGAL's
`wlop_simplify_and_regularize_point_set` (100% kept, default radius) was measured on the quick
subset only (`--wlop`): 11.3 / 7.1 at 1%, worse than the noisy input, at 16 s per cloud; it is a
resampler, not a denoiser, and is left out of the full table. Command:
`build/bench/evaluate pugan --sizes 10000`.

Quoted rows (*italic*): Luo & Hu 2021, Table 1, on *their* PU-Net test clouds (20 meshes,
Poisson-disk sampled), rounded to two decimals; the values were taken from a secondary copy of
that table and not checked against the paper's PDF. They are not on the same clouds as ours
(16 of the meshes, uniform random sampling, which leaves more clean-to-clean Chamfer distance), so
compare them with care. The 50,000-point columns are not in this run (about 25 s per cloud for
the peers' sweeps; `PGD_PUGAN_SIZES=10000,50000 bash scripts/evaluate.sh`).

MID
  cat "$results/pugan.md"
  cat <<'MID2'

## 3. Real scanner noise: the raw Stanford bunny scans

The raw Cyberware range scans `bun000`, `bun045`, `bun090`
(`../shared/data/real/stanford_bunny_scans`, NaN samples dropped) mapped onto the Stanford
reconstruction `bun_zipper.ply` with Stanford's registration (`bun.conf`: p ↦ Rᵀp + t); the mean
distance of the points to the reconstruction, in millimetres, before and after each method (the
peers' settings chosen per scan by that distance; WLOP not run). What is left includes the
registration error, which no denoiser removes. Command: `build/bench/evaluate bunny`.

MID2
  cat "$results/bunny.md"
  cat <<'TAIL'

![bun000 before and after, coloured by the distance to the reconstruction](bunny_bun000.png)

## 4. What the numbers taught: the default refinements

On the PU-GAN meshes the paper's filters with their data-derived γ were far behind the peers
(10K, P2M ×10⁴ at 1 / 2 / 3%: Tikhonov 3.41 / 5.38 / 6.99, TV 2.60 / 3.91 / 4.82 against jet
0.78 / 1.51 / 2.69 on the quick subset of three meshes), and worse than the noisy input at 1%.
Two causes, measured on other meshes (the CAD benchmark's block, joint, part-Lp, casting, the
Stanford dragon and the decimated bunny, 10,000 points, σ = 0.5–2%, γ swept):
- Laplacian smoothing slides points along the surface: they cluster, borders and thin parts
  empty, and P2M's triangle-to-point term grows. Moving each point only along the normal of a
  plane fitted to the smoothed points (two graph rings) cut the best-γ error by 10–25%.
- It shrinks curved surfaces. Twicing (2H(f) − H(H(f)), for Tikhonov the spectral filter
  1 − (1 − h)², flat to second order) cut it by another 5–25% and moved the best γ to the
  data-derived default; a third-order version (1 − (1 − h)³) was no better.
Both are now on by default for both filters; on the quick subset they bring Tikhonov's defaults
from 3.41 / 5.38 / 6.99 to 1.07 / 1.93 / 3.13. Tried and not kept: TV with a Bregman step
(TV(2f − TV(f))) instead of twicing, worse at the cube's edges and overall.

With the refinements, the paper's finding that TV keeps edges sharper than Tikhonov no longer
separates the two defaults: on a noisy cube (30,000 points, σ = 0.01, points within 0.1 of an
edge) the paper's filters give 0.0074 (Tikhonov) and 0.0060 (TV), the refined defaults 0.0045
and 0.0045 (`ctest -R PaperTotalVariationKeepsCubeEdges`).

## Not yet in this report

Outlier benchmarks (1/5/20% outliers on the synthetic shapes and the PU-GAN meshes against
`StatisticalOutlierRemoval`, `RadiusOutlierRemoval` and CGAL `remove_outliers`; the fountain and
table scenes), the 50,000-point PU-GAN columns, and pictures of a sharp-edged CAD mesh.
`ctest -R evaluation_quick` re-checks the claims stated as holding on the quick subsets.
TAIL
} > docs/evaluation.md
echo "wrote docs/evaluation.md, docs/figure3.png and docs/bunny_bun000.png"
