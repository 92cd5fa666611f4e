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
render() { xvfb-run -a -s "-screen 0 1920x1080x24" ./build/bench/render_views "$@"; }
render docs/bunny_bun000.png --size 2400 800 --range 0 0.3 --view 0 0 -1 0 1 0 \
  --scalar-title "distance to the reconstruction (mm)" \
  "raw scan bun000" "$results/bunny_bun000_noisy.pcd" \
  "GraphTVSmoothing, defaults" "$results/bunny_bun000_TV.pcd" \
  "MLS, best radius" "$results/bunny_bun000_MLS.pcd"
p="$results/pugan_fandisk_10000_2_"
render docs/fandisk.png --size 2400 800 --range 0 3 --scalar-title "distance to the mesh (% of the radius)" \
  "noisy, 2%" "${p}noisy.pcd" "GraphTikhonovSmoothing, defaults" "${p}Tikhonov.pcd" \
  "CGAL jet, best k" "${p}jet_best.pcd"
for scene in fountain_sfm_11view fountain_colmap_sparse table_scene_mug_stereo_textured; do
  render "docs/outliers_$scene.png" --size 1600 800 --fit 2 \
    "input" "$results/outliers_${scene}_input.pcd" \
    "kept by GraphDegreeOutlierRemoval (defaults)" "$results/outliers_${scene}_kept.pcd"
done
render docs/kinect_temporal.png --size 2400 800 --range 0 5 --view 0 0 1 0 -1 0 \
  --scalar-title "distance to the next frame's surface (mm)" \
  "raw frame 2 of 3" "$results/kinect_frame1_raw.pcd" \
  "GraphTikhonovSmoothing, frame by frame" "$results/kinect_frame1_per_frame.pcd" \
  "GraphSequenceSmoothing (Tikhonov, k2 = 3)" "$results/kinect_frame1_temporal.pcd"
{
  cat <<'HEAD'
# Evaluation

Regenerate everything on this page with `bash scripts/evaluate.sh` (it installs, builds, runs
`build/bench/evaluate` section by section and writes this page with
`scripts/evaluation_report.sh`). Seeds are fixed: the numbers are reproducible (the times are
not: they are wall-clock seconds on the machine that ran it, 2 cores).

Section 1 measures the paper's filters exactly. Sections 2 and 3 measure the filters as they run
by default, with two refinements beyond the paper (`setNormalDisplacement`, onto blended
quadrics over an adaptive support, and `setShrinkageCorrection`; section 5 says why).

## 1. The paper's experiment (its Figure 3)

A square plane [-1,1]², the unit sphere and the cube [-1,1]³, each sampled uniformly at random
10,000 times; Gaussian noise of standard deviation σ at nine levels from 0.001 to 0.1, spaced
logarithmically; the mean distance of the points to the true surface (exact) for the noisy input,
the paper's filters (`GraphTikhonovSmoothing` and `GraphTVSmoothing` with
`setNormalDisplacement (false)` and `setShrinkageCorrection (false)`) with default parameters
(k = 10, θ and γ derived from the data), and each at the best γ of a sweep over 1/16× to 16× its
default. Command: `build/bench/evaluate figure3`.

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
resampler, not a denoiser, and is left out of the full table. On all 16 meshes at 10,000 points,
on the table's own clouds (same seeds; replayed for WLOP alone, the noisy input's P2M coming out
equal to the table's), it gives CD / P2M 9.49 / 6.80, 13.66 / 10.72 and 18.07 / 14.78 at 1 / 2 /
3% (noisy input: 3.33 / 1.28, 7.93 / 4.35, 13.50 / 9.03), lower than the noisy input's P2M on 4
of the 48 clouds (Icosahedron and star at 2% and 3%), at 8.9 s per cloud; `--wlop` adds this row
to a run. It was not run at 50,000 points.

Quoted rows (*italic*): Luo & Hu 2021, Table 1, on *their* PU-Net test clouds (20 meshes,
Poisson-disk sampled), rounded to two decimals; the values were taken from a secondary copy of
that table and not checked against the paper's PDF. They are not on the same clouds as ours
(16 of the meshes, uniform random sampling, which leaves more clean-to-clean Chamfer distance), so
compare them with care.
MID
  # The sizes this run measured, for the command and the 50,000-point sentence.
  sizes=$(awk '!/^#/ {print $2}' "$results/pugan.dat" | sort -n -u | paste -sd, -)
  # A run with --no-risk has the risk-estimate rows, all not run (nan).
  no_risk=""
  if grep -q '"Tikhonov (risk γ)"' "$results/pugan.dat" &&
     ! grep '"Tikhonov (risk γ)"' "$results/pugan.dat" | grep -qv ' nan '; then
    no_risk=" --no-risk"
  fi
  # A run with --two-ring (ours with setAdaptiveSupport (false)) marks its data.
  two_ring=""
  grep -q '^# adaptive_support 0' "$results/pugan.dat" && two_ring=" --two-ring"
  echo "Command: \`build/bench/evaluate pugan --sizes $sizes$no_risk$two_ring\`. The 50,000-point columns take about 25 s"
  if [[ ",$sizes," == *",50000,"* ]]; then
    echo "per cloud for the peers' sweeps (\`PGD_PUGAN_SIZES=10000,50000 bash scripts/evaluate.sh\`); this"
    echo "run has them."
  else
    echo "per cloud for the peers' sweeps and are not in this run"
    echo "(\`PGD_PUGAN_SIZES=10000,50000 bash scripts/evaluate.sh\`)."
  fi
  if [[ -n "$no_risk" ]]; then
    echo "The rows of the risk-estimate selection (section 5) were not run in it (\`--no-risk\`, about 20"
    echo "runs per cloud)."
  fi
  echo
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

A sharp-edged CAD mesh from the PU-GAN set, fandisk, 10,000 points, σ = 2%, coloured by the
distance to the mesh:

![fandisk: noisy, Tikhonov, jet](fandisk.png)

## 4. Outliers

Synthetic: the plane, sphere and cube of section 1 (10,000 points, σ = 0.005) and the PU-GAN
meshes (10,000 points, σ = 1%), with 1%, 5% and 20% more points added uniformly in the bounding
cube (the bounding box widened to its largest side on every axis, so that the plane gets outliers
off its plane) enlarged by 10%. Precision, recall and F1 of the removed points as outliers, and the time per
cloud. `GraphDegreeOutlierRemoval` with defaults (ε = 3 spacings, automatic τ, residual test
c = 4) and told the true fraction (`setOutlierFraction`, which ranks by degree alone);
`pcl::StatisticalOutlierRemoval` with PCL's tutorial values
(mean K 50, 1 standard deviation); `pcl::RadiusOutlierRemoval` (at least 5 neighbours) at the best
of 1, 2, 3 times the mean 10th-neighbour distance **per cloud** (chosen by F1 against the truth);
CGAL `remove_outliers` (k = 24) with the threshold of CGAL's example (2 average spacings) and told
the true fraction. Command: `build/bench/evaluate outliers`.

The residual test (README, `setResidualThreshold`) is what puts the defaults ahead: an outlier
that lands within about two spacings of the surface has as many close neighbours as a surface
point, and the degree test alone (the paper's filter, `setResidualThreshold (0)`) kept 9–26% of
the outliers here (F1 0.948 / 0.954 / 0.949 on the PU-GAN meshes, 0.869 / 0.871 / 0.838 on the
shapes, behind RadiusOutlierRemoval at its best radius or CGAL in five of the six columns).
Variants tried on the way, on these clouds, noisy spheres (`bench/bench_graph`) and noiseless
and noisy cubes: the plane fitted with the graph's Gaussian weights (two outliers side by side
hid each other: the nearest neighbour dominates the fit); the noise scale taken as the median
residual of the point's 10 nearest neighbours (it removed 150 of 10,000 points of a noiseless
cube, where the residuals fall off steeply beside the edges); the plane's own spread alone (kept
the edges, but a point near an edge whose own face is sparsely sampled went: hence the second
condition, on the plane of all the neighbours); the plane restricted to 3 spacings when ε is
set wider (on the Kinect and KITTI scans it removed 3–5 times more points at a wide ε, many of
them on quantisation steps: hence the layer rule); c = 3 (precision 0.96 on the noisy sphere)
and c = 5 (more outliers kept). For the degree threshold (1,000,000 points at 0.5% noise, where the
noise band is thick against θ and the threshold cuts its tail: F1 0.957 against
RadiusOutlierRemoval's 0.966): a cap at the degree an inlier 4 noise scales s off the surface
keeps, τ ≤ exp(−16 s² / (2 (s² + θ²))) × the lower quartile, gained 0.012 there but lost 0.008
with 20% outliers and up to 0.006 on cubes; the cap exp(−(c² − 1) s² / (2 (s² + θ²))) with the
median of the degrees above a quarter of the median as reference (so that the outliers' number
does not move it) reached 0.967 there and gained 0.0019 in mean F1 over spheres and cubes at
100,000 and 1,000,000 points, 0.2% and 0.5% noise, 5% and 20% outliers, but removed 11–33% of
the real stereo and Kinect scans of `data/real/pcl` (their density varies with depth, and the
sparse half fell below the reference) and 14% of the fountain's points within 5 units: not taken.
Raising θ (and ε with it) to twice the noise level measured on 4,000 points' planes, when that
is above the derived θ (a point z off the middle of a band of standard deviation s keeps about
exp(−z² / (2 (s² + θ²))) of the middle's degree, so a θ small against s cuts the tails): F1 on
the noisy sphere at 1,000,000 points, 0.5% noise, 5% outliers 0.9567 → 0.9693 (2,002 inliers
removed → 233; RadiusOutlierRemoval's best 0.9662, the oracle's 0.9699), at 100,000 points and
2% noise 0.879 → 0.891, unchanged at 0.2% and at 100,000 points and 0.5% (θ is already above
twice the noise there), and none of the real scans of `data/real` but car6 and the displaced
noisy slice have a noise above half their θ; but with 20% outliers at 1,000,000 points 0.9714
→ 0.9689, and on sparse, very noisy spheres (20,000 points, 3% and 4% noise) 0.848 → 0.825 and
0.804 → 0.789: it keeps the tails' inliers and more of the outliers near the band with them.
Not taken (measured with a scratch driver on `synthetic::noisySphere` and
`addUniformOutliers`, the clouds of `bench/bench_graph`). Checked again on 2026-12-03 with θ
alone raised (`setSigma`) and ε left at its derived 3 spacings, to see whether the wider ε
caused the losses: θ = 2 / 3 noise levels (and θ = 1000, the count of neighbours within ε, as
RadiusOutlierRemoval counts) gave F1 0.9687 / 0.9692 (0.9688) at 1,000,000 points, 0.5% noise,
5% outliers (defaults 0.9567), 0.894 / 0.893 (0.893) at 100,000 points and 2% (defaults 0.879),
but 0.9702 / 0.9688 (0.9677) with 20% outliers (defaults 0.9714), 0.829 / 0.808 (0.800) and
0.802 / 0.794 (0.786) on the 20,000-point spheres at 3% and 4% noise (defaults 0.848, 0.804),
and at 100,000 points and 0.2% noise θ = 2 noise levels, below the derived θ, removed 5,828
inliers: the losses come with θ itself (a wider kernel keeps the outliers near the band with the
tails' inliers), not with ε.

A rescue of the tails by a Bayes cut (checked 2026-12-03, evening): keep a point that fails the
degree test when its plane residual is within the band of z noise scales where a surface point
is likelier than an outlier, n φ(z) / s ≥ ρ (n the surface's points per unit area from the
median count of ε-neighbours, ρ the points off the surface or without a plane over the bounding
box; at most c), and its degree is at least the degree the Gaussian band model gives a point z
off the surface, the lower quartile × exp(−z² s² / (2 (s² + θ²))). The band came out at 3.75
noise scales at 1,000,000 points, 0.5% noise, 5% outliers (the model's optimum, with the true
noise, is 3.8), and F1 rose there from 0.9567 to 0.9679 (RadiusOutlierRemoval's best 0.9662,
the oracle's 0.9699), at 100,000 points and 2% noise from 0.879 to 0.892, on the 20,000-point
sphere at 4% noise from 0.8036 to 0.8074; unchanged at 0.2% noise, at 100,000 points and 0.5%,
on noisy cubes of 100,000 and 1,000,000 points and the real clouds of the table below; but
0.8484 → 0.8476 at 3% noise, 0.9714 → 0.9713 with 20% outliers at 1,000,000 points, and 0.001
lower in each column of the PU-GAN meshes (0.951 / 0.958 / 0.954), so that with 20% outliers
the defaults no longer lead RadiusOutlierRemoval at its best radius there. With the floor
referred to the quartile's own place in the band (|z| = 1.15 noise scales, exp(−(z² − 1.32) s² /
(2 (s² + θ²)))) the PU-GAN meshes gave 0.952 / 0.959 / 0.954, the 1,000,000-point sphere 0.9662
(level with RadiusOutlierRemoval), 100,000 points at 2% 0.889, 20,000 at 4% 0.8030. The
residuals are biased low where ε is only a few noise scales (the neighbours of a point off the
middle lie towards it: the median residual gives 0.86 of the true noise at 1,000,000 points), so
outliers just beyond the band pass for surface points and the surface's tail is cut short of the
optimum. The same rescue with the candidates' residuals and the noise scale taken from planes
over a ball of 2 ε (unbiased on the 1,000,000-point sphere: 0.00495 for a noise of 0.005): 0.9685
there and 0.892 at 100,000 points and 2%, but 0.8404 on the 20,000-point sphere at 3% noise
(from 0.8484) and 0.944 / 0.951 / 0.944 on the PU-GAN meshes (from 0.952 / 0.959 / 0.955): over
the wider ball the surface's curvature and detail widen the residuals, and outliers near the
surface pass.
Neither taken (scratch driver on `synthetic::noisySphere`, `synthetic::noisyCube` and
`addUniformOutliers`, and `build/bench/evaluate outliers`).

A kernel no narrower than the noise (checked 2026-12-03, night). Where the noise is wider than
the spacing (the 1,000,000-point sphere at 0.5% noise: spacing 0.0064, noise 0.005), θ = the
spacing is narrower than the band, the band's smoothed density falls to the threshold
(0.2 × the lower quartile) at about 3 noise scales, and the degree test removes the surface's
tails there: 2,002 surface points, where the Bayes cut for 5% outliers lies at about 3.75. Tried:
θ = max(spacing, a s₀) and ε = 3 θ, s₀ the median plane residual / 0.6745 over at most 20,000
queries sampled at the spacing's ε. With a = 2 that sphere gave 0.9693 (removed surface points
2,002 → 198; RadiusOutlierRemoval's best 0.9662, the oracle's 0.9699), and 100,000 points at 2%
noise 0.8786 → 0.8913; but with 20% outliers at 1,000,000 points 0.9714 → 0.9690, the
20,000-point sphere at 3% and 4% noise 0.8484 → 0.8205 and 0.8036 → 0.7830, the noisy cube of
100,000 points at 2% 0.8039 → 0.7725 (a wider kernel lets the outliers near the surface through),
and the PU-GAN meshes 0.952 / 0.959 / 0.955 → 0.949 / 0.957 / 0.951 (behind RadiusOutlierRemoval's
0.954 at 5% and 20%). With a = 1.75: 0.952 / 0.958 / 0.953 there, and the dense sphere only
0.9567 → 0.9578 at a = 1.5. Clouds whose noise is within the spacing (the spheres at 0.2%,
100,000 points at 0.5%, the cubes at 0.5%, the three shapes, the real clouds) do not change. A
fixed θ on the dense sphere: 0.0064 (the default) 0.9563, 0.008 0.9687, 0.01 0.9676, 0.013
0.9622. Not taken: as with the Bayes cuts above, what the dense sphere gains the meshes and the
denser outliers lose (the same scratch driver, and `build/bench/evaluate outliers`).
The Bayes cut above was tried again on 2026-12-07 gated to clouds whose residual noise scale
s is at least half θ (so that the PU-GAN meshes, at about 0.3, would not change): with the
floor quartile × exp(−z² s² / (2 (s² + θ²))) no point was rescued on noisy spheres and cubes of
20,000 and 100,000 points at 0.2–4% noise with 5% and 20% outliers (the points below the
threshold lie beyond about 3 noise scales by the band model, and the Bayes band, from the
surface's density estimated from the typical degree, reached 2.9–3.3), and without the floor
the mean F1 over those 48 clouds fell from 0.8458 to 0.7585 (the outliers near the band came
back). Reverted.
Nor a rescue of low-degree points that lie on their neighbours' plane (2026-12-04): a point
below the threshold kept when its refitted plane's residual is within c noise scales (the
residual test's s₀), c = 2, 2.5 and 3. On noisy spheres and cubes of 100,000 points with 5%
outliers at 0.2–2% noise F1 fell everywhere or stayed (cube at 2%: 0.8039 → 0.7860, 0.7791,
0.7520; sphere at 1%: 0.9394 → 0.9379, 0.9372, 0.9359): the outliers close to the surface lie on
its plane too.

The sparse-surface growth (`setKeepSparseSurfaces`, default since 2026-12-06) came from real
scans, not from these tables: with ε one radius for the whole cloud, the degree test removed a
scanner's far range (PCL's laser room scan lost 67% of its points 5–6 m from the scanner and all
beyond 8 m; the Kinect table scene 37.5% of its points at 1.8–2.1 m). Tried on the way, with
`build/bench/evaluate outliers`, the room scans and a scratch driver over noisy spheres and cubes
of 20,000 to 1,000,000 points at 0.2–2% noise with 5% and 20% outliers (`synthetic::noisySphere`,
`synthetic::noisyCube`, `addUniformOutliers`; mean F1 over its 32 clouds 0.94956 without the
growth): keeping each low-degree point whose 10 nearest neighbours are about as dense as their
own (local outlier factor ≤ 1.5), lie on a plane (flatness ≤ 0.15) with the point on it (offset
≤ 0.3 of their spread): room_scan1 removed 5,648 → 3,474 points but the PU-GAN means fell 0.0013
/ 0.0002 / 0.0004 (1% / 5% / 20%), and flatness ≤ 0.25 or 0.35 cost up to 0.03 (uniform outliers
lie on a plane often enough); 20 or 30 neighbours for the plane kept less of the room. Growth
from the typical points along links of like density (mean 10-NN distance at most 1.25 or 1.5
times the neighbour's), without a plane test: the room kept all but 720–1,112 points, but on the
cube with 20% outliers the growth climbed from the surface into the outliers (F1 0.774 → 0.32–0.54):
their density rises gradually towards the surface. Passing the growth on only through points on
their neighbours' plane stops that: with the plane test at 0.5 of the spread the cube held at a
ratio of 1.25 (0.773) but not at 1.35 (0.540); at 0.45, 0.774 and 0.771; at 0.4 (the default,
for the margin) 0.774 at both, and the 32-cloud mean stays 0.94956 (two clouds changed by one
point). The defaults' F1 in the
tables below is unchanged to the third decimal; room_scan1 removes 3,296, room_scan2 1,400
(from 1,644), the Kinect table scene 452 finite points (from 9,702), and the two fountains of the
table below 1,024 and 1,541 (from 1,141 and 1,607), the gross outliers still removed.
A spinning scanner's far rings stayed out of reach (each point's 10 nearest neighbours lie on
its own ring, so the growth never crosses to it: a Velodyne frame of KITTI still lost 86% of its
points 30–40 m away): a point whose neighbours lie on a line (middle standard deviation at most
0.1, 0.15 or 0.2 of the largest) and that is at most 1.25 times as sparse as their median starts
a growth of its own. 0.1 (the default): the frame removes 5,324 points instead of 8,350 with the
growth alone and 9,292 without it (30–40 m: 21.4% instead of 85.6%), 0.15 and 0.2 only 5,260 and 5,044; the Kinect scenes did not change
(milk_cartoon 452 finite points, office1 one fewer), and the F1 scores above and the scratch
driver's 32-cloud mean (0.94956) neither. Also on 2026-12-06: the residual test fits each
point's plane to its nearest 256 ε-neighbours where the ball holds more (beside the room scan's
scanner a ball held 20,000, and fitting them all took more than half of the filter's time: 9.7 s
→ 5.0 s on one thread; room_scan1 3,296 → 3,326 removed, every cloud of the tables unchanged).
TAIL
  cat "$results/outliers.md"
  cat <<'TAIL'

The real clouds, before and after `GraphDegreeOutlierRemoval` with defaults (one camera for both
views, fitted to the points kept, so the far outliers of the input fall outside the picture):

![fountain, 11-view SfM](outliers_fountain_sfm_11view.png)
![fountain, COLMAP sparse](outliers_fountain_colmap_sparse.png)
![table scene, textured-light stereo](outliers_table_scene_mug_stereo_textured.png)

## 5. What the numbers taught: the default refinements, and the default γ

On the PU-GAN meshes the paper's filters with their data-derived γ were far behind the peers
(10K, P2M ×10⁴ at 1 / 2 / 3% on a quick subset of three meshes: Tikhonov 3.41 / 5.38 / 6.99, TV
2.60 / 3.91 / 4.82 against jet 0.78 / 1.51 / 2.69), and worse than the noisy input at 1%. Two
causes, found on other meshes (the CAD benchmark's block, joint, part-Lp and casting, the
Stanford dragon and the decimated bunny; 10,000 points, σ = 0.5–2%, γ swept):
- Laplacian smoothing slides points along the surface: they cluster, borders and thin parts
  empty, and P2M's triangle-to-point term grows. Moving each point only along the normal of a
  plane fitted to the smoothed points (two graph rings) cut the best-γ error by 10–25%.
- It shrinks curved surfaces. Twicing (2H(f) − H(H(f)); for Tikhonov the spectral filter
  1 − (1 − h)², flat to second order) cut it by another 5–25% and moved the best γ to the
  data-derived default. A third-order version (1 − (1 − h)³) was no better; for TV, a Bregman
  step (TV(2f − TV(f))) instead of twicing was worse at the cube's edges and overall.
On the quick subset these two brought Tikhonov's defaults from 3.41 / 5.38 / 6.99 to
1.07 / 1.93 / 3.13.

What was still missing against jet (a local quadric fit) was measured on 8 of the PU-GAN meshes
(casting, fandisk, kitten, camel, chair, star, genus3, cow; 10,000 points; geometric mean of
P2M ×10⁴ at 1 / 2 / 3%), every variant at the data-derived γ unless stated:

| variant (Tikhonov) | 1% | 2% | 3% |
|---|---|---|---|
| plane + twicing (the previous default) | 0.564 | 1.472 | 2.989 |
| the same at the best γ per cloud (¼×–8×) | 0.449 | 1.345 | 2.880 |
| k = 20 / k = 30 instead of 10 | 0.768 / 1.022 | 1.682 / 1.964 | 2.981 / 3.271 |
| re-graphing: graph rebuilt on the output, the input filtered again | 0.634 | 1.472 | 2.721 |
| the same from a first pass at ½γ / ¼γ | 0.580 / 0.557 | 1.410 / 1.417 | 2.798 / 2.939 |
| the same twice | 0.672 | 1.546 | 2.863 |
| quadric height field fitted to the noisy points over two rings (no smoothing) | 0.577 | 1.399 | 2.378 |
| quadric fitted to the single-solve (shrunk) estimate | 1.690 | 4.467 | 7.183 |
| quadric fitted to the twiced estimate, γ × 1 / ¾ / ½ / ¼ | 0.625 / 0.578 / 0.542 / 0.528 | 1.552 / 1.437 / 1.353 / 1.315 | 2.463 / 2.320 / 2.237 / 2.240 |
| the same, robust (2 re-weightings by the residual, scale σ̂), ½γ | 0.468 | 1.258 | 2.259 |
| robust with scale σ̂/2 / 2σ̂ | 0.483 / 0.486 | 1.275 / 1.284 | 2.298 / 2.228 |
| robust, 4 re-weightings, ½γ / 0.35γ | 0.453 / 0.457 | 1.243 / 1.250 | 2.280 / 2.302 |
| **the own-quadric default** (blended since, end of this section): robust, first weights from the plane through the smoothed point, 4 fits, ½γ | **0.448** | **1.242** | **2.240** |
| the same at ½ / 2 × its γ | 0.425 / 0.547 | 1.232 / 1.443 | 2.340 / 2.417 |
| TV, own-quadric default (½ / 2 × its γ) | **0.409** (0.408 / 0.531) | **1.188** (1.283 / 1.425) | **2.479** (2.609 / 2.738) |
| jet at its best k per cloud (18, 36, 72) | 0.446 | 1.210 | 2.254 |

Larger k and re-graphing helped smooth shapes at high noise and hurt thin ones (casting,
chair), and were not taken. The robust quadric keeps curvature that the plane cuts (chord
error) and ignores points of another sheet (the far side of a thin wall), so the filter needs
less smoothing: the data-derived γ is halved with it (`setLocalSurface (LocalSurface::PLANE)`
keeps the plane and the full γ). The probe runs on evaluation meshes; the halved γ was then
checked on the calibration set kept apart (below).

Feature-aware edge weights were tried and not taken: each k-NN weight multiplied by
exp(−(((fⱼ − fᵢ)·nᵢ)² + ((fᵢ − fⱼ)·nⱼ)²) / (4h²)), h = c σ̂, with the normals nᵢ of the
noisy points over two graph rings (a neighbour off the point's tangent plane, as across a thin
wall or a sharp edge, counts less; the derived γ follows the lower degrees). On the quick subset
(casting, fandisk, kitten; 10,000 points; `build/bench/evaluate pugan --quick`), P2M ×10⁴ of
Tikhonov / TV at 1%: casting 3.01 / 2.09 by default, 2.86 / 2.02 with c = 2, 2.97 / 2.07 with
c = 4; on fandisk and kitten c = 2 was 0–6% worse at every level and c = 4 within 2%. The
casting's loss against its noisy input (1.22) does not come from smoothing across its thin
walls, or not only. The noise estimate is one cause: on the casting at 10,000 points σ̂ is
3.9×, 2.2×, 1.3× and 1.0× the true σ at 0.5, 1, 2 and 3% (fandisk, kitten, camel, genus3,
star, cow: 0.8–1.4×; chair 2.4× at 0.5%), so the derived γ over-smooths it; at a quarter of
that γ Tikhonov's P2M there falls from 3.13 to 2.01 (1%). Other estimators over the same two
rings do not fix it: the residual of a quadric fit instead of a plane gives 3.7× / 2.1× on the
casting (and 1.0–1.2× at 0.5% on the smooth meshes, against 1.2–1.4× for the plane), its
median absolute deviation 2.9× / 2.0×, the lower quartile instead of the median 2.6× / 1.8×:
at this sampling the casting's thin parts are narrower than two graph rings, and no local fit
separates their detail from noise.

At edges: on a noisy cube (30,000 points, σ = 0.01, points within 0.1 of an edge) the paper's
filters give 0.0075 (Tikhonov) and 0.0060 (TV); the plane defaults gave 0.0045 and 0.0045, the
quadric defaults 0.0036 and 0.0036, the blended quadrics (end of this section) 0.0034 and 0.0035,
with the detail term of the derived γ (end of this section) 0.00375 and 0.00402 (TV no longer
sharper: the detail term reads the cube's flat faces and raises γ, TV's more, which rounds the
edges a little more while the faces get flatter), with TV's noise term (end of this section;
σ̂ is a quarter of a spacing there, so TV's γ is halved) 0.00375 and 0.00352, and with the
adaptive quadric support (the default now, end of this section) 0.00328 and **0.00320**
(`ctest -R TotalVariationKeepsCubeEdges`, which asserts it): all sharper than the paper's TV,
and the default TV sharper than the default Tikhonov.

The default γ (γ · mean degree = 20 (σ̂/s)^1.5 for Tikhonov, γ = 10 σ̂ / mean Σ√w for TV, both
halved with the quadric) comes from the paper's filters on spheres and cubes.
`build/bench/calibrate_gamma` sweeps it for the default filters on the calibration set above plus
a sphere and a cube, at 10,000 and 50,000 points and σ = 0.5, 1, 2%. With the plane, the defaults
landed at 1.28× the error of the best of the sweep (geometric mean); with the quadric at 1.17×
(Tikhonov) and 1.11× (TV), and the best power law in σ̂/s does no better (1.16×, 1.11×). The best
multiple is ¼–1 on detailed meshes (casting, dragon at 10,000 points), 1–2 on the bunny, 2–4 on
the cube and 8–16 on the sphere: the noise-to-spacing ratio cannot tell a detailed surface (less
smoothing) from a smooth one (more). Nor could a constant factor (with the plane: twice the
default γ improved the raw bunny scan bun000, 0.0839 → 0.0798 mm, and the demo's scene, but
worsened the PU-GAN quick subset, 1.07 → 1.83 at 1%). A rule that reads the surface's detail
came later: the detail term at the end of this section.

The 50,000-point PU-GAN columns (section 2, first run with them) show the derived γ too weak at
that density: the best multiple of the ¼×–4× sweep was 2× or 4× on 10 of 16 meshes at 1%
(Tikhonov; 14 of 16 for TV), on 14 of 16 at 2% (15 for TV), and 4×, the end of the sweep, on 14
of 16 at 3% (15 for TV), where at 10,000 points it is ½×–2× on most meshes. There the defaults
trail jet and MLS (P2M 2.54 for Tikhonov, 3.56 for TV, against 1.67 and 1.64), while Tikhonov at
its best γ (1.61) matches them. The density term of the rule, (σ̂/s)^1.5, grows too slowly with
the density; recalibrating it (on the calibration set, not on these meshes) is the next step.

A first pass of that recalibration (`build/bench/calibrate_gamma`, now at 10,000, 20,000 and
50,000 points, σ = 0.5, 1, 2 and 3%, multiples in steps of √2; stopped after the block, the
joint and part-Lp, 36 clouds) confirms it on meshes kept apart: at a fixed σ the best multiple of
the derived γ grows with the density (Tikhonov: ¼–1.3 at 10,000 points, 0.7–1.9 at 20,000,
1.5–3.8 at 50,000; TV up to 8), and the derived γ then costs up to 1.5× (Tikhonov) and 1.9× (TV)
the error of the best one at 50,000 points and 3%. A least-squares fit gives best multiple ∝
σ̂^0.88 s^−2.06 (Tikhonov) and σ̂^1.26 s^−2.20 (TV), i.e. γ · mean degree ∝ σ̂^2.4 / s^3.6: not
invariant to the cloud's unit. On these clouds, all scaled to the unit sphere, the object's
size is the missing third length; a rule that stays unit-free needs a length measured on the
surface (its feature size, e.g. from the curvature of the quadric fits), which is the open work.
Both inputs of the rule also blur at high noise: the k-NN spacing grows with the noise (block,
50,000 points: 0.0178 at σ = 0.5%, 0.0283 at 3%, the distance to neighbours inside a thick
shell) and σ̂ falls short of σ (0.0225 for 0.03). The rest of the set (run afterwards with
`calibrate_gamma --only casting,dragon,bun_zipper,sphere,cube`, as far as it got) shows what the
third length must capture: the best multiple is ¼, the floor of the sweep, on the casting at
10,000 and 20,000 points, ¼–0.7 on the dragon at 10,000, 0.5–1 on the bunny at 10,000 rising to
2–4 at 50,000, and 8–16, the ceiling, on the sphere at every size (where the derived γ costs
1.4–2.3× the best error). Detail the quadric cannot follow limits γ, density raises it, and a
surface of constant curvature takes any γ: the rule needs a measure of the surface's detail.

**The two inputs of the rule, corrected for noise (a first sweep).** A second sweep (a
one-off program, not kept: the default filters at ¼–64 × the derived γ in steps of 2, on the
calibration set's eight shapes at 10,000 and 50,000 points and σ = 0.5, 1, 2, 3%, 64 clouds;
error over the best of the sweep, interpolated between multiples, geometric mean) measured how
far each input of the rule is off and what correcting it buys:
- The k-NN spacing grows with the noise: against the surface's own spacing (1/√density,
  from the median count m of points within R = 3 k-NN spacings, s = √(π(R² − 1.45σ²)/m), within
  1% of the truth on noisy planes up to σ = 3s) it is 1.3–1.4× at low noise and up to 2.4× at
  50,000 points and 3%.
- The two-ring noise estimate saturates when the noise nears the spacing. On noisy planes
  (160,000 points) σ̂/σ is 0.98 at σ = s/2, 0.96 at σ = s, 0.81 at 2s, 0.65 at 3s and 0.43 at
  6s, the same function of σ/s as on the meshes (0.63–0.76 at 50,000 points and 3%). Inverting
  that table (with the corrected spacing, iterated) brings σ̂ to 0.98–1.17 σ there. Plane fits
  over a ball instead (R = 3 k-NN spacings, or 4σ̂ iterated) reach only 0.8–0.9 σ at 50,000
  points and 3% and give 2–6 σ on the casting, whose thin walls they straddle.
- With both corrections and the best refitted power law γ·(mean degree) ∝ (σ̂/s)^b, the error
  over the best goes from 1.199 to 1.177 for Tikhonov and from 1.158 to 1.110 for TV (the
  meshes alone, without the sphere and the cube: 1.101 → 1.081 and 1.130 → 1.075). The gain is
  at 50,000 points (Tikhonov 1.268 → 1.201, TV 1.248 → 1.099) and is paid at 10,000 (1.133 →
  1.153, 1.075 → 1.122), so the refitted rule was not taken (the corrected σ̂ alone was: below).
- With the true σ in place of σ̂ the same fit reaches 1.047 (Tikhonov) and 1.040 (TV) on the
  meshes. What is left to gain is in the noise estimate at low noise on detailed surfaces,
  where the two-ring plane residual counts detail as noise (σ̂ = 3.9 σ on the casting, 2.1 σ on
  the dragon, 1.3–1.4 σ on the joint and part-Lp at 10,000 points and 0.5%), more than in
  the density term.
- The one-ring lead, built into the filters and measured (next paragraph): the plane fit
  over the one ring (the vertex and its neighbours) instead of two, corrected by its own
  noisy-plane table. On the calibration meshes it gave 1.0–1.3 σ at every size and level but
  one (the casting at 10,000 points and 0.5%: 2.2 σ, against 4.0 σ for the two rings under
  the same correction).

**The noise estimate, corrected where the noise nears the spacing (the default).**
`core::estimateNoise` keeps the two-ring plane residual and divides its median by the factor
a noisy plane shows at the same noise over spacing: 0.99 at a tenth of the spacing, 0.98 at
half, 0.96 at one, 0.81 at two, 0.65 at three (`build/bench/calibrate_gamma --noise-table`,
160,000-point planes, three seeds), with the surface spacing from the median count of points
in a ball of 4 mean 10-NN distances, solved together with the level. On those planes it
recovers the noise within 2.2% and the spacing within 1.8% up to five spacings of noise. At
low noise it reads what the two rings read (the Stanford scan bun000 and the Kinect table
scene: 1–2% more), and at 50,000 points and 3% it reads 1.00 σ on the sphere and on fandisk
(the uncorrected two rings: 0.83 and 0.60). The same 64-cloud sweep, with the rules
unchanged, as error over the best of the sweep:

| | all 64 clouds | 10,000 points | 50,000 points | the 48 mesh clouds |
|---|---|---|---|---|
| Tikhonov, two-ring σ̂ (before) | 1.199 | 1.133 | 1.268 | 1.101 |
| Tikhonov, **corrected two-ring σ̂** | **1.171** | 1.135 | **1.208** | **1.072** |
| Tikhonov, corrected one-ring σ̂ (not taken) | 1.167 | 1.119 | 1.218 | 1.067 |
| TV, two-ring σ̂ (before) | 1.158 | 1.075 | 1.248 | 1.130 |
| TV, **corrected two-ring σ̂** | **1.131** | **1.071** | **1.196** | **1.099** |
| TV, corrected one-ring σ̂ (not taken) | 1.126 | 1.059 | 1.197 | 1.091 |

The one-ring estimate was as good on these synthetic clouds, whose noise is independent from
point to point, and worse on real scans: a range scanner's noise is correlated over
neighbouring samples, and a patch of 11 points takes part of it for surface. On bun000 it read
55 µm where the two rings read 97 µm (the scan's mean distance to the reconstruction is 90 µm),
and the default filters' distance to the reconstruction rose from 0.0803 to 0.0824 mm
(Tikhonov; bun045 0.0786 → 0.0808, bun090 0.1006 → 0.1035); on the Kinect table scene it read
0.488 mm against 0.615 mm and left the table less flat (TV, near / mid / far RMS 0.824 / 1.165
/ 2.001 mm against 0.821 / 1.129 / 1.954). Refitting the rules with the one-ring estimate and
the surface spacing in place of the k-NN spacing did not pay either: for Tikhonov on the
meshes the current rule was the best power law of σ̂ over the k-NN spacing (exponent 1.5,
constant 20), the surface spacing in its place did no better (1.169 against 1.167 overall),
and for TV twice its constant would give 1.097 overall and 1.093 at 50,000 points but 1.101 at
10,000 (against 1.059). The sphere (best multiple 8–32) is what keeps the overall figure above
the meshes' one.

On the PU-GAN meshes (section 2, the same clouds; `build/bench/evaluate pugan --sizes
10000,50000 --no-risk`) the defaults moved as follows (P2M ×10⁴ at 1 / 2 / 3%): Tikhonov
0.56 / 1.33 / 2.24 → 0.58 / 1.38 / 2.30 at 10,000 points and 0.14 / 0.69 / 2.54 → 0.14 /
0.61 / 1.80 at 50,000; TV 0.47 / 1.22 / 2.44 → 0.48 / 1.24 / 2.37 and 0.16 / 1.03 / 3.56 →
0.16 / 0.88 / 2.93. Over the best of MLS, jet and bilateral smoothing on each cloud (each at
its best setting for that cloud), Tikhonov's geometric mean went from 1.151 to 1.060 (10,000
points 0.993 → 1.005, 50,000 points 1.334 → 1.118), beating all three on 43 of the 96 clouds
(45 before); TV's from 1.387 to 1.296 (1.013 → 1.004, 1.899 → 1.673), 35 of 96 (30 before). At
10,000 points and 2–3%, where the noise is about the spacing, the correction raises σ̂ by a
few percent, which these meshes did not want; at 50,000 points it closes most of the gap to
the best γ of the sweep (Tikhonov at 3%: 1.80 against 1.53, was 2.54 against 1.61). The raw
bunny scans (section 3) moved by at most 0.0001 mm.

**Choosing γ by a risk estimate** (`setGammaSelection (GammaSelection::RISK_ESTIMATE)`,
`-gamma risk`; `core::selectGammaByRisk`). Instead of a measure of detail, the filter can
measure its own error without ground truth. For Gaussian noise of level σ per axis, Stein's
lemma gives an unbiased estimate of the squared error along the normals nᵢ of any denoiser F:
R = Σᵢ (nᵢ·(F(f)ᵢ − fᵢ))² − Nσ² + 2σ² div F, and the divergence is estimated by one random probe,
div F ≈ Σᵢ zᵢ nᵢ·(F(f + ε z n)ᵢ − F(f)ᵢ) / ε with zᵢ standard normal. The filter runs its whole
pass (solve, twicing, quadric) at the rule's γ × ¼, ½, 1 … 16, then one step of √2 on each side of
the best, and keeps the lowest R (σ = σ̂; on more than 50,000 points, four blocks of 12,500
consecutive vertices in the Morton order, which keep the density). Two details decided whether it
worked, measured with Tikhonov on 36 clouds (casting, bunny, block, dragon, sphere, cube; 10,000
and 50,000 points; σ = 0.5, 1, 3%; error of the chosen multiple over the best of the sweep,
geometric mean; the rule 1.23×): with a small probe (ε = σ̂/10) and the normals of the noisy
points, 1.14×, failing at 3% noise (bunny, block, sphere at 50,000 points: 2.2–4.6×) — the
robust quadric fit jumps between sheets, which a small step does not see, and noisy normals
count tangential moves; with ε = σ̂ and the normals of the points denoised at the rule's γ,
1.08×. Its remaining misses: the sphere at 50,000 points and 3% (2.9×, the rule 3.3×), where σ̂ is
0.82 σ, and the casting, where σ̂ is 2.2 σ at 1%: with the true σ the estimate picks the best
multiple there (TV, ¼ against 1 with σ̂).

`build/bench/calibrate_gamma` (the library's filters; 44 clouds: the casting at 10,000, 20,000
and 50,000 points, the dragon, the bunny, the sphere and the cube at 10,000 and 20,000; σ = 0.5,
1, 2, 3%; `--only dragon,bun_zipper,sphere,cube --sizes 10000,20000` for the second part) gives,
as the error over the best of the sweep (geometric mean):

| | rule | risk estimate | the sphere (8 clouds): rule / risk | the casting (12): rule / risk |
|---|---|---|---|---|
| Tikhonov | 1.195 | **1.039** | 1.82 / 1.01 | 1.19 / 1.09 |
| TV | 1.104 | **1.052** | 1.35 / 1.04 | 1.08 / 1.12 |

On the quick PU-GAN subset (casting, fandisk, kitten; 10,000 points; P2M ×10⁴ at 1 / 2 / 3%),
Tikhonov goes from 1.20 / 2.03 / 2.79 to 0.97 / 1.89 / 2.78 (its best γ: 0.84 / 1.69 / 2.51;
jet 0.78 / 1.51 / 2.69), TV stays (0.89 / 1.72 / 2.77 → 0.90 / 1.79 / 2.76). The price is time:
2.9 s against 0.19 s per 10,000-point cloud for Tikhonov, 8.2 s against 0.31 s for TV (measured
while another job ran). On all 16 PU-GAN meshes at 10,000 points (`build/bench/evaluate pugan
--sizes 10000`, 48 clouds; P2M ×10⁴ at 1 / 2 / 3%; the 50,000-point run is still to come):

| | mean P2M | beats every peer | geometric mean over the best peer (1 / 2 / 3%) |
|---|---|---|---|
| Tikhonov, rule | 0.56 / 1.32 / 2.27 | 31 of 48 | 0.996 (1.015 / 1.023 / 0.954) |
| Tikhonov, **risk estimate** | **0.50 / 1.24 / 2.19** | **33 of 48** | **0.940** (0.951 / 0.960 / 0.910) |
| Tikhonov, best of ¼–4× (an oracle) | 0.46 / 1.17 / 2.13 | 35 of 48 | 0.911 |
| TV, rule | 0.47 / 1.20 / 2.45 | 27 of 48 | 1.009 (0.939 / 1.008 / 1.084) |
| TV, risk estimate | 0.47 / 1.21 / 2.31 | 30 of 48 | 0.969 (0.936 / 0.983 / 0.991) |
| MLS / jet / bilateral, each at its best setting per cloud | 0.53 / 1.50 / 2.82, 0.51 / 1.25 / 2.34, 0.64 / 1.49 / 3.30 | | |
| *GLR (quoted)* | *1.05 / 1.31 / 2.11* | | |

With the risk estimate both filters lead every peer's mean at every level, Tikhonov gets two
thirds of the way from the rule to the oracle, and only GLR's 3% figure stays below ours. The
goal set for the defaults (ahead of the best peer on 80% of the clouds, at 0.9× its error) is
not reached by it either: 69% and 0.94×. Time per cloud: Tikhonov 2.39 s against 0.17 s by the rule, TV 7.06 s against 0.23 s. So
it stays an option. (The risk figures in this paragraph and the two tables above were measured
with the noise estimate before its correction for noise near the spacing, described above; at
10,000 points the correction changes σ̂ by a few percent.)

With the blended quadrics (end of this section) the same run (`build/bench/evaluate pugan
--sizes 10000`: 48 clouds, other seeds than section 2's run at both sizes) gives:

| blended quadrics | mean P2M | beats every peer | geometric mean over the best peer (1 / 2 / 3%) |
|---|---|---|---|
| Tikhonov, rule | 0.54 / 1.18 / 2.03 | 38 of 48 | 0.889 (0.927 / 0.899 / 0.844) |
| Tikhonov, **risk estimate** | **0.52 / 1.16 / 2.01** | **39 of 48** | **0.870** (0.920 / 0.869 / 0.824) |
| Tikhonov, best of ¼–4× (an oracle) | 0.44 / 1.02 / 1.90 | 41 of 48 | 0.816 |
| TV, rule | 0.45 / 1.10 / 2.28 | 34 of 48 | 0.926 (0.871 / 0.912 / 0.999) |
| TV, risk estimate | 0.50 / 1.12 / 2.18 | 34 of 48 | 0.909 (0.931 / 0.889 / 0.909) |
| TV, best of ¼–4× (an oracle) | 0.41 / 1.02 / 2.04 | 38 of 48 | 0.846 |

At 10,000 points Tikhonov with the risk estimate meets the goal (81% of the clouds, 0.87×), and
with the rule nearly (79%, 0.89×); the risk estimate gains less than before (0.889 → 0.870,
against 0.996 → 0.940 with the own quadric). Time per cloud in this run, beside two other jobs
on the two cores: Tikhonov 5.6 s against 0.34 s by the rule, TV 19.6 s against 0.65 s.

On a million points it fails. `build/bench/bench_smoothing 1000000` (noisy unit sphere,
σ = 1%): the rule's γ leaves a mean distance of 0.00315, while 4×, 16× and 64× its γ give
0.00152, 0.00058 and 0.00024 (MLS at its best radius 0.00086); the risk estimate chose 1×, on
four blocks of 12,500 vertices, on four of 50,000 and on the whole graph alike (2× on the blocks
with the true σ instead of σ̂ = 0.67 σ). There the noise is 2.6 times the spacing, as at 50,000
points and 3% where it also fell short: every two-ring neighbourhood lies inside the noise, σ̂
falls short and the estimate with it. It then cost 13.5 s against 5.9 s for Tikhonov, 39.3 s
against 11.8 s for TV (the graph alone 1.1 s). The same run shows how far the rule's density term falls short at that
size: more than 64× on a sphere, where it is 8–16× at 10,000–50,000 points. With σ̂ corrected
for noise near the spacing (above; it now reads the sphere's σ where the two rings read 0.67 σ),
the same benchmark gives 0.00238 for the rule's γ (Tikhonov; TV 0.00452 → 0.00389) and 0.00200
for the risk estimate (TV 0.00379 → 0.00247), 4 × the rule's γ 0.00105: better, and still far
from the best γ and from MLS. It took 5.9 s for Tikhonov and 14.0 s for TV (13.5× the graph
build, was 10.8×: a larger γ takes the TV solver more iterations), 14.1 s and 49.8 s with the
risk estimate.

**Blending the quadrics (the default).** Each vertex's robust quadric is fitted to about 30
points, and the point moved onto it carries that fit's own noise: the fits of neighbouring
vertices, which share most of their points, disagree by about as much. As overlapping patch
estimates are aggregated in image denoising, `LocalSurface::BLENDED_QUADRICS`
(`core::quadricDisplacement` with `QuadricProjection::BLENDED`) moves fᵢ along the normal of
every vertex j of its two rings onto j's quadric and takes the weighted mean of those
positions, with weight exp(−d²/(2(rⱼ/2)²) − e²/(2σ̂²)): d the tangential distance of the
smoothed xᵢ from xⱼ, rⱼ the RMS tangential spread of j's rings (rⱼ/2 is about its one ring's
reach), e the distance of xᵢ from j's surface along its normal (a patch of another sheet drops
out). Every vertex's patch (17 doubles) is kept between two passes over the rings. The variants,
Tikhonov at the derived γ on the PU-GAN clouds of section 2 (same seeds, replayed by a one-off
program; geometric mean of P2M over the best peer per cloud, and in brackets the clouds, of 48,
where it beats every peer):

| blending (Tikhonov, derived γ unless stated) | 10,000 points | 50,000 points |
|---|---|---|
| none: the own quadric (the previous default) | 1.005 (30) | 1.118 (13) |
| one ring, equal weights | 0.913 (39) | |
| one ring, Gaussian reach rⱼ / ½ rⱼ | 0.916 / 0.930 (39 / 39) | |
| one ring, residual weight at σ̂; with reach rⱼ too | 0.917 / 0.918 (39 / 39) | |
| two rings, equal weights | 0.912 (36) | |
| two rings, reach rⱼ, residual weight at σ̂ | 0.906 (35) | |
| **two rings, reach ½ rⱼ, residual weight at σ̂ (taken)** | **0.888 (38)** | **1.055 (19)** |
| the same with reach 0.7 rⱼ / 0.35 rⱼ | 0.891 / 0.915 (37 / 38) | 1.152 / 1.020 (16 / 21) |
| the same without the residual weight / with it at 2σ̂ | 0.921 / 0.897 (38 / 38) | 1.020 / 1.018 (25 / 23) |
| taken, at ½ / 0.7 / 1.4 × the derived γ | 0.896 / 0.882 / 0.926 (36 / 36 / 39) | – / – / 0.944 (30) |
| taken, at 2 / 4 × the derived γ | | 0.901 (34) / 1.238 (13) |

The variants were compared on the evaluation's own meshes; what decides for other data, the
blend against the own quadric at the same γ, was then measured on the calibration set kept apart
(the eight shapes of `calibrate_gamma` at 10,000, 20,000 and 50,000 points and σ = 0.5, 1, 2,
3%, 96 clouds): the blend's error over the own quadric's is 0.911 for Tikhonov (0.72–0.98, lower
on every cloud) and 0.940 for TV (up to 1.018, the sphere at 50,000 points and 3%). The derived
γ stays: over the best of ⅓–4 × per cloud (Tikhonov, 10,000 and 50,000 points, 64 clouds) it
lands at 1.124, 1.4 × at 1.113, 2 × at 1.144 and 0.7 × at 1.158. The PU-GAN clouds want 0.7 ×
at 10,000 points and 2 × at 50,000: the rule's density term again (above), which no constant
factor fixes.

In section 2's run (`build/bench/evaluate pugan --sizes 10000,50000 --no-risk`), over the best
of MLS, jet and bilateral smoothing per cloud, each at its best setting for that cloud (the rows
before the detail term are from the previous runs, on the same clouds):

| defaults, geometric mean over the best peer (clouds where it beats every peer) | 10,000 points | 50,000 points | all 96 |
|---|---|---|---|
| Tikhonov, own quadric | 1.005 (30) | 1.118 (13) | 1.060 (43) |
| Tikhonov, blended quadrics | 0.888 (38) | 1.055 (19) | 0.968 (57) |
| **Tikhonov, blended quadrics, detail term (then the default)** | **0.871 (39)** | **0.873 (35)** | **0.872 (74)** |
| the same, best of ¼–4 × γ per cloud (an oracle) | 0.813 (42) | 0.823 (39) | 0.818 (81) |
| TV, own quadric | 1.004 (27) | 1.673 (8) | 1.296 (35) |
| TV, blended quadrics | 0.926 (33) | 1.746 (11) | 1.272 (44) |
| TV, blended quadrics, detail term | 0.911 (31) | 1.211 (15) | 1.050 (46) |
| the same, best of ¼–4 × γ per cloud (an oracle) | 0.850 (38) | 0.919 (32) | 0.884 (70) |
| **TV, blended quadrics, detail and noise terms (then the default)** | **0.940 (34)** | **0.959 (30)** | **0.949 (64)** |
| the same, best of ¼–4 × γ per cloud (an oracle) | 0.854 (38) | 0.914 (33) | 0.884 (71) |

Those defaults' mean P2M (×10⁴) was below GLR's quoted figures at every level for Tikhonov: 0.52 /
1.17 / 2.01 at 10,000 points and 0.10 / 0.51 / 1.58 at 50,000 (GLR 1.05 / 1.31 / 2.11 and 0.16 /
0.83 / 2.71); TV's at or below them but at 10,000 points and 3% (0.50 / 1.31 / 2.37 and 0.11 /
0.57 / 1.58; with the detail term alone 0.46 / 1.13 / 2.22 and 0.12 / 0.72 / 2.42). Against the
goal of this section (ahead of the best peer on 80% of the clouds, 0.9 × its error): Tikhonov's
geometric mean holds at both sizes (0.871, 0.873), its share of wins does not (74 of 96, 77%; 81
of 96 at its best γ); TV, with its noise term (below), comes to 0.940 and 0.959 (64 of 96), from
1.211 at 50,000 points where its γ was too weak on most meshes. The losses left are the
detailed meshes at 10,000 points (casting 1.3–1.9 ×, chair 1.2–1.4 × the best peer with
Tikhonov, best γ at the ¼ × floor of the sweep): the noise estimate counts their detail as noise
(σ̂ up to 4 σ on the casting) and the detail term reads their thin parts by amplitude. On the
casting at 10,000 points the defaults even leave more error than the noisy input (Tikhonov 2.82
against 1.25 at 1% and 4.47 against 3.62 at 2%, TV 2.66 and 4.86; TV also on the chair at 1%,
1.09 against 1.07): the clouds of section 2's findings where they do not lower it. The raw bunny
scans (section 3) moved from 0.0792 / 0.0777 / 0.0996 to 0.0780 / 0.0765 / 0.0974 mm with the
detail term (Tikhonov; TV 0.0793 / 0.0778 / 0.0997 to 0.0775 / 0.0759 / 0.0952, and with its
noise term 0.0788 / 0.0772 / 0.0978: σ̂ is small against the spacing there and TV's γ is
lowered, where 4 × suits it best), Tikhonov ahead of every peer on bun000, behind jet on bun045
and bun090. Time per cloud (section 2's run, idle machine): Tikhonov 0.104 s at 10,000 points and
0.39 s at 50,000, TV 0.15 and 0.71 s (0.14 and 0.81 s before the preconditioned solver below,
at a weaker γ).

**Adaptive quadric support (the default since these measurements; `setAdaptiveSupport
(false)`, `-adaptive_support 0` for two rings everywhere).** Each vertex's quadric is fitted over its three graph rings instead of
two where that wider fit agrees with the two-ring one (the two fits' surfaces, evaluated under
the two-ring points, within √6 × 2σ̂ in root-sum-square: an intersection of confidence
intervals, as in Katkovnik's LPA-ICI), so that smooth parts average more noise and edges, thin
parts and detail keep the narrow fit (`core::QuadricSupport::ADAPTIVE` of
`core::quadricDisplacement`). Alone (x = f, blended) it was within 2% of the better of two and
three rings everywhere on a noisy sphere (three rings 33% better there) and a corrugated sheet
(two rings 14% better). With the two-ring rule's γ it over-smoothed Tikhonov (a first run on 48
PU-GAN clouds at 10,000 points, `evaluate pugan --sizes 10000 --no-risk`, whose seeds differ
from the table's: Tikhonov's defaults 0.871 (39 clouds ahead of every peer) → 0.875 (37), TV's
0.939 (34) → 0.854 (36) over the best peer). The γ for it was then chosen on the calibration set
kept apart (`calibrate_gamma --sizes 10000 --no-risk`, with and without `--two-ring`; 32 clouds:
the six meshes, the sphere and the cube at σ = 0.5, 1, 2, 3%; error over the best of both
sweeps, geometric mean): two rings at their rule 1.150 (Tikhonov) and 1.196 (TV); adaptive
support at ¼ / 0.35 / ½ / 0.7 / 1 × the rule 1.092 / 1.089 / 1.092 / 1.103 / 1.127 (Tikhonov)
and 1.095 / 1.088 / 1.086 / 1.093 / 1.113 (TV). The adaptive support therefore halves the derived γ. At
½ × against two rings at the rule, per shape (geometric mean over its four noise levels):
block 0.98, joint 0.94, part-Lp 0.94, casting 1.06, dragon 1.03, bunny 0.99, sphere 0.86, cube
0.83 for Tikhonov; 0.95, 0.93, 0.92, 0.96, 1.00, 0.94, 0.77, 0.83 for TV.

On section 2's clouds (section 2's table is measured with it; `build/bench/evaluate pugan
--sizes 10000,50000 --no-risk --two-ring` gives the two-ring rows; the same seeds, the peers'
rows identical), over the best of MLS, jet and
bilateral smoothing per cloud, each at its best setting for that cloud (clouds where it beats
every peer in brackets):

| geometric mean over the best peer | 10,000 points | 50,000 points | all 96 |
|---|---|---|---|
| Tikhonov, two rings (the previous default) | 0.871 (39) | 0.873 (35) | 0.872 (74) |
| **Tikhonov, adaptive support (the default)** | **0.811 (39)** | **0.692 (43)** | **0.749 (82)** |
| the same, best of ¼–4 × γ per cloud (an oracle) | 0.768 (40) | 0.640 (46) | 0.701 (86) |
| TV, two rings (the previous default) | 0.940 (34) | 0.959 (30) | 0.949 (64) |
| **TV, adaptive support (the default)** | **0.797 (39)** | **0.692 (43)** | **0.743 (82)** |
| the same, best of ¼–4 × γ per cloud (an oracle) | 0.753 (41) | 0.649 (46) | 0.699 (87) |

Mean P2M (×10⁴) at 1 / 2 / 3%: Tikhonov 0.51 / 1.18 / 1.94 at 10,000 points and 0.09 / 0.43 /
1.18 at 50,000, TV 0.47 / 1.14 / 1.99 and 0.09 / 0.41 / 1.18: below every peer's mean and below
GLR's quoted figures at every level (1.05 / 1.31 / 2.11 and 0.16 / 0.83 / 2.71). Both filters
lower the noisy input's P2M on 94 of the 96 clouds; the exceptions are the casting at 10,000
points and 1–2%, whose detail the noise estimate reads as noise (above). These clouds meet
the goal of this section (ahead of the best peer on 80% of the clouds, at 0.9 × its error or
less) with either filter: 85% of the clouds, 0.75 ×. Near the edges of the noisy cube of the
edge test (30,000 points, σ = 0.01, points within 0.1 of an edge) it gives 0.00328 (Tikhonov)
and 0.00320 (TV), against 0.00375 and 0.00352 over two rings: TV stays the sharper. The price is
time, the second fit of every vertex: in the same runs of `build/bench/bench_smoothing`
(a sphere and a cube of 100,000 and of 1,000,000 points) 1.26–1.61 × the two-ring time for
Tikhonov and 0.94–1.17 × for TV. (Sections 2, 3 and 6 do not compare across runs: this machine
ran the regenerated tables about twice as slowly as the previous ones, the peers too, e.g. MLS
0.075 s per 10,000-point cloud against 0.034 s and 0.28 s per bunny scan against 0.11 s.)
Where it does not help: the raw bunny scans (section
3, measured with it; `evaluate bunny --no-risk --two-ring` for two rings), whose best γ is 4 ×
the rule's, lose a little with the halved γ: Tikhonov 0.0787 / 0.0774 / 0.0985 mm against
0.0780 / 0.0765 / 0.0974 over two rings, TV 0.0790 / 0.0777 / 0.0990 against 0.0788 / 0.0772 /
0.0978. On a million points
(`build/bench/bench_smoothing 1000000`, σ = 1%, one run) the cube gains (Tikhonov 0.00091
against 0.00104, TV 0.00106 against 0.00132; MLS at its best radius 0.00113) and the sphere
is mixed (Tikhonov 0.00044 against 0.00038, where twice the rule's γ gives 0.00024: the halved
γ is too weak there; TV 0.00088 against 0.00096), at 1.6 × and 1.1–1.2 × the time (sphere:
22.8 s against 14.3 s for Tikhonov, 33.2 s against 29.6 s for TV; 13.9 × and 20.2 × the graph
build, which took 1.64 s in this run against 0.86 s in the earlier one above: this machine's
speed varies between runs). At 100,000 points (`bench_smoothing 100000`, one run) the same:
the cube gains (Tikhonov 0.00155 against 0.00168, TV 0.00164 against 0.00201), the sphere
loses for Tikhonov (0.00081 against 0.00067) and gains for TV (0.00112 against 0.00135): on a
dense smooth sphere the halved γ is too weak for Tikhonov. On these figures it became the default, and this page was
regenerated with it (sections 2, 3 and 6; sections 1 and 4 do not use the quadrics). The
factor ½ was fitted at 10,000 points. On the calibration set at 20,000 and 50,000 points
(`calibrate_gamma --sizes 20000,50000 --no-risk`, 64 clouds, with it) the rule is 1.083
(Tikhonov) and 1.080 (TV) × the error of the best of its sweep, and the best constant multiple
of the rule grows with the size: 0.71 / 1 × at 10,000 points (1.059 / 1.056; the same seeds
rerun), 1.41 × at 20,000 (1.070 against 1.071 at the rule; TV 1.059 against 1.064) and 1.41 × at
50,000 (1.068 against 1.096; TV 1.070 against 1.096). The detail term's L / s, which grows with
the density, answers part of it: a fit over the 96 clouds of the three sizes of m = c (L / (40 s))ᵇ
(r / 0.5)ᵉ (r = noise / spacing, on top of the current rule) gives c = 1.2, b = 0.2, e = −0.2
for Tikhonov (1.076 → 1.066) and c = 1.3, b = 0.4, e = −0.3 for TV (1.072 → 1.051), almost all of
it on the sphere (Tikhonov 1.259 → 1.147, TV 1.181 → 1.024) and the cube, while the casting
(1.16) and part-Lp (1.10–1.13), whose best multiple falls with the noise where the estimate
reads their detail as noise, stay where they are (a grid search over c, b and e for the lowest
geometric mean, each cloud's error interpolated between the multiples of its sweep, from the
tool's raw lines, which carry L / s). Not yet a default. A first check, that factor on top of
the current rule (an experimental build): the raw bunny scans gain (Tikhonov 0.0781 / 0.0766 /
0.0969 mm against 0.0787 / 0.0774 / 0.0985, TV 0.0782 / 0.0766 / 0.0955 against 0.0790 / 0.0777
/ 0.0990; TV then ahead of every peer on bun000), while section 2's clouds at 10,000 points
(`evaluate pugan --sizes 10000 --no-risk`) stay where they were: over the best peer 0.814 (38
of 48 ahead) against 0.811 (39) for Tikhonov, 0.794 (38) against 0.797 (39) for TV. At 50,000
points, where the calibration set gained most, it does not hold up (`evaluate pugan --sizes
50000 --no-risk`, that build and the current one in the same session, 48 clouds; point-to-mesh
error, geometric mean over the clouds): Tikhonov 1.006 × the current default's (lower on 18
clouds, higher on 7, the rest equal to the table's two decimals), ahead of every peer on 41
clouds against 42, 0.689 × the best peer against 0.684; TV 1.031 × (1.070 × at 3% noise), 39
ahead against 42, 0.705 × the best peer against 0.684. With the 10,000-point clouds (Tikhonov
a little worse, TV a little better) the PU-GAN meshes do not gain from it: the calibration
set's gain was its sphere and cube. Not taken (section 6 was not run for it). The dense smooth
sphere's under-smoothing (below: at a million points its best γ is 4 × the default) stays open.

Variants of the adaptive support tried on the raw bunny scans (whose losses to jet, at its
widest k = 72, suggested that a wider fit would help), not taken: a third step, four rings where
their fit agrees with the three-ring one by the same test: Tikhonov 0.0794 / 0.0781 / 0.0989 mm
against 0.0787 / 0.0774 / 0.0985, worse. Wider robust weights in the quadric fits (the weight
exp(−t² / 2) with t the residual over c σ̂ instead of σ̂): the bunny scans gain, with c = 2
Tikhonov 0.0778 / 0.0764 / 0.0960 and TV 0.0780 / 0.0766 / 0.0965, with c = 3 0.0776 / 0.0760
/ 0.0952 (ahead of jet on bun000), but the calibration set at 10,000 points loses at the default
γ (`calibrate_gamma --sizes 10000 --no-risk --default-only`, geometric mean error over its 32
clouds): Tikhonov 2.59 × 10⁻⁴ at c = 1, 2.75 at 1.5, 2.86 at 2, 2.97 at 3 (TV 2.58, 2.71, 2.82,
2.93). The scanner's correlated noise, which the two-ring estimate reads short, wants the wider
weights; Gaussian noise does not. The noise level scaled by 1.5 in the whole quadric step (fits,
agreement test, move limit, blend): bunny Tikhonov 0.0780 / 0.0765 / 0.0958.

On a million points (`build/bench/bench_smoothing 1000000`, noisy unit sphere, σ = 1%, the
noise 2.6 spacings) the blend costs: Tikhonov 0.00247 against 0.00239 with the own quadric, TV
0.00444 against 0.00389, and 7.5 s against 5.7 s, 15.8 s against 13.3 s (7.2× and 15.0× the graph
build, were 5.7× and 13.5×). There the derived γ was far too weak (4 × the rule's γ gave 0.00103;
the detail term below answers it) and the smoothed points the patches are fitted to stay noisy; a narrower reach (0.3 rⱼ) gives
0.00232 and 0.00412 there, but cost the PU-GAN clouds at 10,000 points (0.35 rⱼ above).

**A detail term in the rule (the default now).** The measure of detail that the sweeps above
asked for, in a unit-free form: the length L over which the surface bends, read on the noisy
cloud (`core::estimateNoise`, `NoiseEstimate::curvature` = 1/L). Around every vertex of a cloud
under 8,000 points, else every ⌊n / 4,000⌋-th (4,000 to 6,000 balls), the points within R = 6 mean 10-NN distances (at least 12; 10
whatever the graph's k) give a covariance whose
smallest eigenvalue, less σ̂², is the squared thickness t of the patch; a surface of curvature κ
has t ≈ κR² / (4√3), and 1/L is the mean of t / R² (a sphere of radius r reads L = 4√3 r,
within 15% from 10,000 to 50,000 points, unit-free: test `NoiseLevel.MeasuresHowTheSurfaceBends`).
With the quadric surfaces the halved rule (halved again by the adaptive support, the default
since the end of this section) is multiplied by L / (40 s) for Tikhonov and
L / (30 s) for TV, s the mean k-NN distance, clamped to [⅛, 16] (`core::detailGammaFactor`); the
plane surface and the paper's filters keep the rule. Both constants and the exponent of L / s
come from a one-off sweep (the default filters at ⅛–16 × in steps of √2 on the calibration set's
shapes at 2,500, 5,000, 10,000 and 50,000 points), checked on the PU-GAN meshes. Error over the
best of that sweep per cloud (geometric mean):

| | rule | rule × detail term |
|---|---|---|
| Tikhonov, calibration set, 2,500 / 5,000 / 10,000 / 50,000 points | 1.159 / 1.134 / 1.134 / 1.223 | 1.097 / 1.082 / 1.087 / 1.092 |
| Tikhonov, PU-GAN, 10,000 / 50,000 points | 1.104 / 1.306 | 1.086 / 1.091 |
| TV, calibration set, 2,500 / 5,000 / 10,000 / 50,000 points | 1.085 / 1.074 / 1.078 / 1.359 | 1.073 / 1.056 / 1.058 / 1.190 |
| TV, PU-GAN, 10,000 / 50,000 points (14 meshes) | 1.098 / 1.377 | 1.083 / 1.120 |

The factor spans ½–14 for Tikhonov (median 0.75 on the calibration clouds at 2,500 points,
1.36 on the PU-GAN clouds at 50,000) and reaches the cap of 16 for TV on spheres; on a sphere of
20,000 points at σ = 1% it is 5.6 (Tikhonov) and 7.4 (TV) and the mean distance falls from
0.00215 to 0.00149 and from 0.00229 to 0.00174 (`ctest -R DetailTermFitsTheStrengthToTheSurface`).
It also answers the density term: L / s grows with the density as the best multiple did. Tried
and not taken: exponents 0.75 and 1.25 of L / s (Tikhonov over the best, all clouds: 1.095 and
1.091 against 1.089 with 1); the median or the RMS of t / R² instead of the mean; a ball of 3
spacings (alone it reads mostly noise; as the larger of the two readings a noisy plane read
more bending than the sphere of the same spacing, 0.18 against 0.13); the curvature of the
quadric fits in the ball; the cloud's extent in spacings. What it cannot see: detail finer than
about twelve spacings is read by its amplitude, not its length, and gets too much smoothing (a
corrugated square: 1.4–1.9 × the plain rule's γ where ¼ × is best; `-gamma risk` still finds
it, `ctest -R RiskEstimate.FollowsTheSurfacesDetail`). The noise estimate itself stays high on
detailed meshes at 10,000 points (σ̂ / σ median 1.1–1.4, the casting up to 4), and giving the
rule the true σ instead gained little. On the Kinect table (`parameters.md`) the derived γ
rises 3× (Tikhonov) and 4× (TV) and the table flattens further; the sequences of section 6 take
the same static γ.

On a million points (`build/bench/bench_smoothing 1000000`, σ = 1%, the noise 2.6 spacings,
idle machine) the detail term fixes most of what the density term lacked: on the unit sphere
Tikhonov's defaults give 0.00038 (was 0.00247; 2 × its γ 0.00024) and TV's 0.00110 (was
0.00444, the best of its ¼–4 × sweep), against 0.00086 for MLS at its best radius and 0.00621
for jet smoothing; on the cube [−1, 1]³ 0.00104 (Tikhonov, the best of its sweep) and 0.00141
(TV) against 0.00113 (MLS; jet 0.00550). The price is time, TV's above all: its larger γ takes
its solver many more iterations (at 4 × the 500-iteration limit is reached). Sphere: Tikhonov
9.1 s and TV 38.0 s, 11.3 × and 47 × the graph build (0.81 s; were 7.2 × and 15.0 ×); cube
7.3 s and 28.1 s (9.5 × and 36.6 ×); MLS at its best radius 17.2 s and 12.7 s. The risk
estimate, which searches around the rule's γ on four blocks of 50,000 points, now chooses too
little there: 0.00130 (Tikhonov) and 0.00247 (TV) on the sphere.

**A noise term in TV's rule, and a preconditioned TV solver (the default now).** TV's rule is
linear in σ̂ (γ = 10 σ̂ / mean Σ√w, a length), Tikhonov's goes as (σ̂/s)^1.5; with the detail
term TV's best multiple still grew with r = σ̂ / s on the calibration set (`calibrate_gamma
--sizes 10000,50000`, 45 clouds of the CAD parts, dragon and bunny): about ½ at r = 0.25, 1–2
at 0.5, 3–4 at 0.8, 4–8 at 1.2 (the casting at 10,000 points aside: ¼ everywhere, its σ̂ is its
detail). With the quadric surfaces TV's halved rule is now also multiplied by
`core::noiseGammaFactor` = (r / 0.5)^1.5, clamped to [½, 3], and the two terms together are held
within [⅛, 16] (`core::refinedGammaFactor`). Fitted on the calibration set's sweeps alone (error
over the best of the sweep, geometric mean): 1.145 → 1.088 (10,000 points 1.067 → 1.094, 50,000
points 1.240 → 1.081). Tried on the same sweeps: exponents 1 and 2 (1.096, 1.092), the clamp
[1, 3] (1.089; it keeps TV's γ on the cube below, and TV then stays blunter than Tikhonov at the
edges), [¼, 4] (1.090), [½, 2] (1.098); Tikhonov's sweeps ask for no such term ((r / 0.7)^1.5 in
[1, 2] at best: 1.084 → 1.077, the casting against it). On the PU-GAN meshes (section 2's run):
TV's defaults 1.050 → 0.949 over the best peer (10,000 points 0.911 → 0.940, 50,000 points 1.211
→ 0.959), 46 → 64 clouds ahead of every peer; its best multiple of ¼–4 × is now 1 × on 54 of 96
clouds (½ × on 22, 2 × on 10). The price: the raw bunny scans 1.7–2.7% worse for TV (above) and
the 10,000-point clouds at 3% (2.22 → 2.37, above GLR's 2.11).

The larger γ would have cost TV's solver more iterations, so the solver changed too
(`core::solveTotalVariation`): the primal-dual algorithm is now diagonally preconditioned (Pock
and Chambolle 2011: each vertex's step 1 / Σⱼ√wᵢⱼ, each edge's dual step 1 / (2√wₑ)) and
accelerated by a global scale of the steps with the data term's modulus of strong convexity in
that metric, the smallest vertex step. Iterations to the default gap of 10⁻³ on a noisy sphere
of 100,000 points at ¼ / ½ / 1 / 2 / 4 / 8 × TV's rule: 20 / 30 / 50 / 80 / 110 / 160 before, 20
/ 20 / 30 / 40 / 50 / 70 now (0.79 s → 0.36 s at 8 ×); at 20,000 points and 8 ×, 110 → 50
(`ctest -R StrongSmoothingConvergesInFewIterations` asserts at most 80). Tried: the same steps
accelerated with the mean vertex step instead of the smallest (80 iterations at 8 ×, but it
diverged on the fountain scan's weakly linked pieces: a gap of 1.9 after 500 iterations and
points thrown 12 spacings; `ctest -R SmoothingThrowsNoPointAway` now checks convergence), and the
preconditioned steps without acceleration (130 at 8 ×). On the fountain scan the default TV now
converges in 90 iterations (250 before).

On a million points (`build/bench/bench_smoothing 1000000`, same clouds as above, idle
machine) the noise term changes nothing on the sphere (the terms' product stays at its cap of
16; σ̂ is 2.6 spacings) and raises TV's γ 1.75 × on the cube (to the cap), and the solver
converges: TV's defaults give 0.00096 on the sphere (0.00110 when its solve stopped at 500
iterations) in 18.8 s instead of 38.0 s, and 0.00132 on the cube (was 0.00141; the best of its
sweep) in 17.1 s instead of 28.1 s: 21.8 × and 20.3 ×
the graph build (0.86 and 0.84 s in this run; were 47 × and 36.6 ×; the target of 6 × is still
far), about MLS's time at its best radius (1.06 ×), which it beats on the sphere (0.00086) and
not on the cube (0.00113). Tikhonov is unchanged: 0.00038 and 0.00104 in 9.7 s and 7.4 s (11.2 ×
and 8.8 × the graph build, target 2 ×). TV's sweep on the sphere now finds 4 × its γ best
(0.00069): converged, a stronger TV keeps gaining there. Where Tikhonov's time goes (`perf` on
300,000 points, one thread, 7.1 s): the blended quadrics about half (their robust fits and the
blend's weights), the two conjugate-gradient solves of the twicing 28% (166 iterations), the
graph and the noise estimate most of the rest; no one piece would bring it near 2 ×.

**Faster quadric fits and conjugate-gradient steps, the same output (2026-12-03).** The robust
quadric fits, half of Tikhonov's time, now form their normal equations from the 15 + 6 distinct
moments of each ring (summed two points at a time over the ring stored as columns, the same sums
on every machine), compute their robust weights in a loop of their own, evaluate heights in
scalars, and call Eigen's condition estimate only when the LDLT pivots are far apart; the
adaptive support compares its two fits on the fits' own samples; the Tikhonov solver fuses its
step, residual and preconditioning into one pass over the vertices (three passes per iteration
instead of four). The output is the same to rounding (largest difference 7 × 10⁻¹⁶ on a
200,000-point sphere). The quadric step on a noisy 1M-point sphere (two threads, a profiling
harness, three interleaved runs each) went from 17.1–19.7 s to 13.5–15.0 s; single-threaded at
200,000 points it is 1.42 × faster. `build/bench/bench_smoothing 100000` (two runs on a busy
machine, σ = 1%): Tikhonov's defaults 1.13–1.40 s on the cube and 1.29–1.45 s on the sphere, TV's
1.76–1.82 s and 2.13–2.56 s, against a graph build of 0.09–0.10 s and 0.14 s: 9.2–13.7 ×
(Tikhonov) and 15.2–19.4 × (TV) the graph build, still far from the 2 × and 6 × targets; against
MLS at its most accurate radius 0.76–1.02 × its time (Tikhonov) and 1.19–1.68 × (TV; it was
1.15 × and 1.69 × before). Not done: collecting each vertex's rings by stamping a per-thread
table of the cloud's size (about 8% of the fits' time, for 4 bytes per point and thread), and a
faster exponential for the robust weights (glibc's takes 8–10 ns; Eigen's vectorised one was no
faster without AVX in a first try, but see the end of this paragraph). On a million points in
the same session (`build/bench/bench_smoothing 1000000`; the graph build took 1.93 s on the sphere and 1.70 s on the cube, twice the 0.86 s of
the runs above: the machine was slower, so compare the ratios): Tikhonov's defaults 0.00044 in
17.5 s on the sphere and 0.00091 in 20.0 s on the cube (9.1 × and 11.8 × the graph build), TV's
0.00088 in 27.4 s and 0.00106 in 28.5 s (14.3 × and 16.7 ×); MLS at its most accurate radius
0.00086 in 26.3 s and 0.00113 in 21.6 s, jet smoothing 0.00621 and 0.00550 in 13.4 s and 13.2 s.
Tikhonov is ahead of MLS in error and time on both (0.66 × and 0.93 × its time), TV on the cube
and not on the sphere (1.04 × and 1.32 × its time). The sweeps put the sphere's best γ at 4 × the
default for both filters (Tikhonov 0.00020, TV 0.00046: the default is 2.16 × and 1.91 × the
best's error); on the cube the defaults are the best of the sweep or within 3% of it. Later
the same day the robust weights' exponentials were taken over each ring at once, after their
exponents, with Eigen's vectorised exp (the same output to rounding: at most 1.4 × 10⁻¹⁴ apart
on a noisy 1M-point sphere); the quadric step single-threaded at 200,000 points (two passes per
run, three interleaved runs each, idle machine) took 6.92–7.36 s against 7.69–8.03 s, and on
two threads at 1,000,000 points 10.3–10.7 s against 10.7–12.1 s.

**Quadrics at fewer vertices (`setPatchCover`, the default since 2026-12-04).** Each point
blends the quadrics of its two rings, about 40 of them, fitted over rings that share most of
their points, and every one of those fits is two robust fits (two and three rings): half of
Tikhonov's time at a million points. Now a vertex fits a quadric of its own only when fewer than
c of its graph neighbours before it in the graph's (Morton) order have one
(`core::patchCentres`, one pass in order), and every point blends the quadrics of its two rings
as before; a point whose quadrics all ignore it keeps the smoothed point. On noisy spheres and
cubes c = 1 leaves 15% of the vertices with a quadric, c = 2 28%, c = 3 39–41%. On the
calibration set kept apart (`calibrate_gamma --default-only --no-risk`, 96 clouds, each run's
geometric mean error) against a quadric at every vertex: c = 1 +1.9% (Tikhonov) and +2.0% (TV),
c = 2 +0.95% and +0.95%, c = 3 +0.66% and +0.66% (at most +3.8% and +4.0% on one cloud; the
CAD parts' edges lose most, part-Lp +1.6%, the sphere and the cube +0.1%); the whole run took
99 s at c = 1 and 106 s at c = 2 against 136 s. A wider blend did not buy the loss back (the
tangential reach at 0.6 and 0.75 instead of 0.5 at c = 2: +0.9% and +1.4% for Tikhonov, +1.0%
and +1.6% for TV). c = 3 became the default; c = 0 gives the previous output bit for bit. On
the PU-GAN clouds of section 2 (regenerated with it) the defaults' geometric mean over the best
peer went from 0.749 to 0.757 (Tikhonov) and from 0.743 to 0.748 (TV), ahead of every peer on
82 of 96 clouds either way; Tikhonov's mean at 10,000 points and 1% is now 0.5136 against jet's
0.5124 (its finding in section 2 no longer holds there), TV's 0.4775. The bunny scans of
section 3 are unchanged to four digits. Time: on a noisy 1,000,000-point sphere (σ = 1%, the filters with their defaults on two threads, a
scratch driver, runs interleaved) Tikhonov took 9.7–10.3 s at c = 3 against 17.9 s at c = 0
(error 0.000443 against 0.000440), TV 19.9 s against 26.4 s (0.000888 against 0.000885); the
graph build is 1.0–1.5 s of that, so Tikhonov stays at 7–10 × it (target 2 ×) and TV at 13–20 ×
(target 6 ×): the two solves of the twicing (149 conjugate-gradient iterations at 1M points, 3.7
s) and TV's primal-dual iterations (70 and 90, about 0.1 s each) are now the larger part.
`build/bench/bench_smoothing` prints the rows at c = 0 beside the defaults.

**Looser solver tolerances where quadrics are fitted (the default since 2026-12-04).** After the
solves every point moves along its normal onto quadrics fitted to the smoothed points; what a
solve leaves short of its minimiser is a small, smooth displacement that the fits take in. So
the filters' default tolerance now follows the pipeline (`setTolerance`): with the fits, 10⁻⁴
for Tikhonov's conjugate gradient (relative residual) and 10⁻² for TV's relative primal-dual
gap; without them (the paper's filters, section 1, and the plane) the solvers' own 10⁻⁵ and
10⁻³; a tolerance set is used everywhere. On the calibration set kept apart (`calibrate_gamma
--default-only --no-risk`, 96 clouds, against the solvers' own tolerances): Tikhonov the same
geometric-mean error (× 0.99997, every cloud within 0.16%), TV 0.2% less (× 0.9978, −2.0% to
+0.7% on one cloud). On the noisy 1,000,000-point sphere (σ = 1%, the filters with their
defaults on two threads, a scratch driver timing `filter`, two runs each): Tikhonov 150 → 106
conjugate-gradient iterations (the twicing's two solves), 8.4–8.8 s → 7.3–7.8 s; TV 160 → 100
primal-dual iterations, 16.5 s → 12.3–12.4 s; the errors unchanged (0.000443 and 0.000884). The
rest of Tikhonov's time is the graph, the noise estimate and the quadrics; with a quadric at
every vertex (c = 0) the same run takes 12.2 s (Tikhonov) and 17.4 s (TV), so the cover's share
is now 0.6 × and 0.7 ×. The k-NN graph of the same points took 0.74 s on that machine
(`bench_graph 1000000`): Tikhonov is still about 10 × it and TV 17 × (targets 2 × and 6 ×). On
the PU-GAN clouds (section 2, regenerated with it) the defaults' geometric mean over the best peer stayed
at 0.757 for Tikhonov (0.818 at 10,000 points, 0.700 at 50,000) and went from 0.748 to 0.746
for TV (0.800 and 0.695), ahead of every peer on 82 of 96 clouds either way; their mean time per
cloud fell against jet smoothing's in the same run from 1.01 × to 0.83 × (Tikhonov, 10,000
points) and 0.54 × to 0.44 × (50,000), TV 1.29 × to 0.97 × and 0.87 × to 0.63 ×. The bunny
scans of section 3 moved by at most 0.0001 mm; the synthetic sequences of section 6 within
0.5% per row (TV's temporal rows 0.4% lower on average), and the fixed Kinect's consecutive
frames after TV on the temporal graph 1.78 → 1.85 mm apart (median; Tikhonov unchanged at 1.92
mm). Tried on the way and not taken: starting the
twicing's second TV solve from the first one's duals (10 fewer iterations at 1M points at 10⁻²,
0.5% more error there); a block symmetric-SOR preconditioner for the conjugate gradient (fixed
blocks of 4,096 vertices, so that the result does not depend on the threads): 81 → 44–48
iterations at ω = 1–1.7 on that sphere, but each application costs about another Laplacian
product, so no time; and TV's dual update taken over each row's entries as columns, which the
compiler vectorises (the same output bit for bit): 5% per iteration, the loop being bound by
memory traffic rather than arithmetic.

**An early stop for the robust quadric fits (the default since 2026-12-05).** Each quadric was
four least-squares fits, each weighting the ring's points by their residual to the one before;
now the remaining fits are skipped once a fit after the first moves the surface by at most a
tenth of the noise level at every point of the ring (the next weights would differ by a few
percent). On the calibration set kept apart (`calibrate_gamma --default-only --no-risk`, 96
clouds) the geometric-mean error went from 0.000136603 to 0.000136481 (Tikhonov) and from
0.000137974 to 0.000137878 (TV), every cloud within −1.2% to +0.6%. On a noisy
1,000,000-point sphere (σ = 1%, two threads, a scratch driver of its own seed, old and new
library interleaved) the quadric step went from 3.83–3.95 s to 3.16–3.21 s (best of three,
three runs each), and the filters with their defaults (three runs each) from 8.2–9.5 s to
7.5–8.9 s (Tikhonov) and from 15.6–15.9 s to 13.8–15.3 s (TV), their errors unchanged to three
significant digits (0.000446 and 0.000893). The k-NN graph of those points took 0.68 s in the
same session (`bench_graph 1000000`, median of 3): Tikhonov is still 11–13 × it and TV 20–22 ×
(targets 2 × and 6 ×); the filters took longer in this session than in the paragraph above
(7.3–7.8 s and 12.3–12.4 s there, another driver and seed, on another day). The change came
after the last regeneration of the tables of sections 2, 3 and 6 (2026-12-04; sections 1 and 4
fit no quadrics); by the calibration set it moves them by about 0.1%. Tried the same day and
not taken: fewer fits always, three (−0.9% and −0.6% on the calibration set, but the noisy
cubes' edges up to +2.0%), two (−1.9% and −0.6%, the cubes up to +8.9%: the extra fits are what
keeps the other face out at a sharp edge), one (+3.6% and +7.4%); a looser stop at 0.3 noise
levels (−0.7% and −0.5%, the cubes up to +2.3%); the blend's exponentials taken over each ring
at once with Eigen's vectorised exp (no faster: 3.95–4.09 s against 3.83–3.99 s for the quadric
step in separate interleaved runs; the blend's cost is in collecting the rings and reading the
neighbours' patches); the fits' robust weights by the single-precision exp, relative to the
largest (no faster within the machine's run-to-run spread). And, bit for bit the same output,
the covariance of a vertex's rings summed once for its two-ring and its three-ring fit (the
three-ring fit adds only the third ring's points): kept.

**The total-variation solver's dual update vectorised (2026-12-05).** Each primal-dual
iteration updates the dual of every stored graph entry and projects it onto its ball: a
square root and a division per entry, branchy scalar code whose chain of latencies, not memory
traffic, set the pace (without the projection the pass took about a third of the time). The
entries of a row are now taken 32 at a time: their differences gathered first, then the step
and the projection over the batch, branch-free, with the duals stored one array per coordinate,
so that the compiler vectorises the square roots and divisions (`total_variation.cpp` is
compiled without errno and trap semantics, neither of which changes a value); the duality
gap's total variation the same way. The output is the same bit for bit (`calibrate_gamma
--default-only --no-risk` identical at every printed digit; the hash of a 1,000,000-point
solve identical). On a noisy 1,000,000-point sphere (σ = 1%, two threads, γ = 0.0565 as the
filter derives it, 50 iterations at 10⁻², a scratch driver, old and new library interleaved, idle
machine) one TV solve went from 4.20–4.24 s to 2.41–2.87 s (84 → 48–57 ms per iteration); the
TV filter with its defaults (two solves and the quadrics) from 12.4–12.8 s to 10.0–10.2 s in two
of three runs (12.9 s in the third). Against the k-NN graph of those points (0.75–0.96 s in the
same runs) TV is still about 13 × (target 6 ×). Rerun with the final library (which also starts
cold at a γ far above the derived one, two more passes per solve): 3.99–4.16 s against
2.40–2.58 s. The attempt of 2026-12-04 (the paragraph on tolerances above) measured 5% and
took the loop to be bound by memory traffic; runs here with another process busy on the
machine gave erratic differences too, so these were taken on an idle one.

**The conjugate gradient without its stored preconditioned residual (2026-12-06).** Each
iteration wrote the Jacobi-preconditioned residual z = r / (1 + 2γ d) to an array of its own
and read it back for the next direction; it is now computed where it is used, from r and the
diagonal (one 3-column array fewer written and read per iteration; the same output bit for
bit, the hash of a 1,000,000-point solve identical). One solve on a noisy 1,000,000-point
sphere (σ = 1%, 60 iterations at 10⁻⁴, two threads, a scratch driver, old and new library
interleaved, idle machine): 27.5–28.1 ms per iteration → 26.1–27.2 ms, about 4%: the
Laplacian product's pass over the graph is the larger part. Tried the same day and not
taken: a looser tolerance for the twicing's second solve only (its error enters the result
once where the first's enters twice): 3 × the default moved the calibration set's
geometric-mean error (`calibrate_gamma --default-only --no-risk`, 96 clouds) by +0.11%
(Tikhonov) and +0.07% (TV), 10 × by +0.75% and +0.37%, for a few iterations of one solve of
two.

**Mixed-precision conjugate gradient, buffers on huge pages, parallel sums (2026-12-06, night).**
Three changes that leave the output as it was, measured on the noisy 1,000,000-point sphere
(σ = 1%, two threads, scratch drivers; this machine's run-to-run spread was large, so old and
new library were interleaved). (1) The conjugate gradient now solves for the correction of
x = f with its vectors in single precision (the sums in double), recomputes the residual of
the result in double, and continues in double precision only where that residual is still
above the tolerance (a tight tolerance, a γ too strong for single precision, a signal near
3 × 10³⁸); the product is taken as (1 + 2γ d_i) p_i − 2γ Σ w_ij p_j. The twicing's two solves
(60 + 48 iterations at 10⁻⁴): 2.954 s → 2.474 s (best of 7), the same iterations and
residuals; the calibration set unchanged at every printed digit (`calibrate_gamma
--default-only --no-risk`: 0.000136481 and 0.000137878). (2) A page fault costs about 2.7 ms
per MiB on these virtual machines, and the solvers and the quadric step of a Tikhonov call
allocated about 400 MB afresh at a million points (TV's more): their N × 3 signals, the
solvers' vectors, TV's duals (146 MB per solve) and the blend's patches now ask for
transparent huge pages (as the graph build already did), and the blend keeps a patch only for the 40% of vertices that carry one (52 MB
instead of 136). With the kernel set to huge pages everywhere (`always`) the remaining gain was
within the spread (the core's stages 6.41 s against 6.52 s). (3) TV's square roots of the
weights and its duality gap's sums over the vertices ran serially; now in parallel. The
filters with their defaults, before all three (the library of 2026-12-06, evening) and after,
interleaved: Tikhonov 7.7–8.5 s → 6.8–7.5 s, TV 11.7–12.1 s → 9.05–9.2 s in a quiet hour;
later, on a busier machine, Tikhonov 8.3 / 10.2 / 10.0 s → 8.1 / 8.7 / 7.0 s and TV 12.0 /
14.1 / 11.6 s → 10.8 / 10.8 / 9.5 s. Where Tikhonov's time goes now (the core's stages, best of
three): graph 0.84 s, noise estimate 0.25 s, the two solves 2.52 s, the quadric step 3.11 s,
6.75 s in all, still about 8 × the graph build (target 2 ×); within the quadric step, in
CPU seconds over both threads, collecting the two rings 0.37 s, the two-ring fits 1.05 s,
adding the third ring 1.10 s and the three-ring fits 1.97 s, and the blend about 0.9 s of
wall time; on this sphere the three-ring fit is taken at 99.99% of the centres (and at 20,000
points at all of them). Tried and not taken: looser Tikhonov tolerances where quadrics are
fitted, 3 × 10⁻⁴ (108 → 88 iterations; the calibration set's geometric mean +0.02%, but the
20,000-point cube at 0.5% noise +2.1%) and 10⁻³ (67 iterations, +0.05%, one cloud +4.1%); the
direction update fused into the next product in single precision (slower: each neighbour's
new direction computed from its residual, 3.3 s against 2.9 s for the two solves); the
product as p_i + 2γ Σ w_ij (p_i − p_j) in single precision (2.47 s against 2.30 s in the same
runs, kept for the check in double only). Not done: a per-thread stamp table of the cloud's
size for collecting rings instead of the hash set (0.77 s → 0.60 s for the two rings of every
vertex on one thread: about 0.1 s of the filter). A lead for later: the three-ring fit first,
and the two-ring fit only where it could win, the agreement tested by one least-squares
quadric fitted to the three-ring surface's residuals under the two-ring points (the sum of its
squared heights there against the same 6 × (2 noise levels)²). The quadric step on the 1M
sphere went from 2.9–3.1 s to 2.46 s (the two-ring fit is skipped at nearly every centre) with
the error unchanged (0.0004429 against 0.0004433), but on the calibration set (`calibrate_gamma
--default-only --no-risk`) it moves single clouds by up to ±18%: with the three-ring fit's
robust weights on those residuals the geometric mean +0.20% (Tikhonov) and +0.05% (TV), 36 clouds
worse by more than 1% and 18 better; unweighted −0.04% and −0.32% (27 worse, 18 better; the
noisy CAD block, joint and part-Lp and the noisiest bunny and dragon gain up to 13%, the
casting loses 3.5–10.8% at every size and noise); with the weights of the plane through the
point (the two-ring fit's first weights) +0.34% and +0.45%. Not taken as such: the casting's
detail is what the two-ring fit is there for. Taken instead (the default since the same
night): that test only as a shortcut where it clearly agrees, its sum of squares at most 0.05
of the bound, and elsewhere both fits and the comparison as before (bit for bit the old
decision there). On the calibration set every cloud moved by at most 0.4% (geometric mean
0.000136481 → 0.000136491 Tikhonov, 0.000137878 → 0.000137875 TV; at 0.25 of the bound up to
4%, the casting); the quadric step of the 1M sphere 3.03–3.22 s → 2.63–2.90 s in interleaved
runs, its error unchanged (0.0004433).

**Coarse levels for the conjugate gradient (2026-12-07).** Jacobi preconditioning leaves the
smooth directions slowest: their eigenvalues 1 + 2γλ lie at the bottom of the spectrum, while
the diagonal 1 + 2γd is large at the filters' strengths (2γ × the mean degree of a few
hundred). The graph's vertices are stored in Morton order, so a run of 16 consecutive vertices
is a small patch of the surface: each run becomes a vertex of a coarse graph whose operator is
the Galerkin product Pᵀ(I + 2γL)P (P constant on the run: the runs' sizes on the diagonal plus
2γ times the Laplacian of the summed weights between runs), runs of 8 coarse vertices make the
next level, and the last, at most 256 vertices, is solved by dense Cholesky
(`src/core/aggregation.h`). The preconditioner is Jacobi on the graph itself plus a symmetric
V-cycle on the coarse levels (damped Jacobi, ω = 0.7, before and after each coarse
correction): no extra product with the graph's own matrix, the residual's restriction summed
in the pass that updates it, and its share of r · z taken on the coarse level. On the noisy
1,000,000-point sphere (σ = 1%, γ as the filter derives it, the twicing's two solves at 10⁻⁴,
two threads, a scratch driver, old and new library interleaved): 60 + 48 → 29 + 21 iterations,
2.10–2.36 s → 1.52–1.57 s (the coarse levels cost about 40 ms to build per solve and 5 ms per
iteration); the Tikhonov filter with its defaults 6.53 / 6.77 / 6.53 s → 5.77 / 6.06 / 5.77 s,
its error unchanged (0.0004433). `build/bench/bench_smoothing 1000000` in the same session:
sphere Tikhonov 5.87 s (7.49 s the night before), TV 8.65 s (10.07), the graph build 0.96 s:
6.14 × and 9.04 × it (were 7.62 × and 10.23 ×; targets 2 × and 6 ×); cube Tikhonov 5.15 s
(5.40), TV 7.82 s (7.95), graph 0.67 s: 7.73 × and 11.74 × (were 8.60 × and 12.66 ×; the
cube's derived γ is a third of the sphere's, so its solves were shorter already); Tikhonov
0.21 × and 0.22 × the time of MLS at its most accurate radius and 0.44 × and 0.39 × jet
smoothing's, errors unchanged (0.00044, 0.00091). The coarse levels add about 14 bytes per
point to Tikhonov's peak memory (`bench_memory 1000000`: 395.3 bytes per point, from
381.0). The calibration set (`calibrate_gamma --default-only
--no-risk`): every cloud within ±0.21%, geometric mean 0.000136491 → 0.00013649 (Tikhonov;
TV, which does not use the conjugate gradient, unchanged). Two things the first version got
wrong, both caught by the tests: a vertex without links (a far point) shared its run's coarse
correction and left its place by 10⁻⁷ (now it belongs to no aggregate, and its result is its
input exactly); and in single precision the product (1 + 2γd_i) p_i − 2γ Σ w_ij p_j of the
smooth directions the coarse levels add cancels to about p_i, so that at 2γ × the largest
degree of about 2 × 10⁹ the phase diverged (now the coarse levels serve a phase only where 2γ × the largest degree ×
the precision's epsilon is at most 10⁻², single precision up to about 1.7 × 10⁵; beyond,
Jacobi alone as before, and the phase in double precision keeps them to about 10¹⁴). Tried on
the way (the same sphere, a double-precision prototype, iterations to 10⁻⁴ for one solve where
Jacobi took 67): the V-cycle from the graph itself (damped Jacobi on the graph before and after
the coarse correction) 15–18 iterations, but two more products with the graph per iteration;
the additive form on every level (Jacobi on each level, prolonged and summed, no smoothing)
46–47; runs of 8 or 32 vertices for the first level 30 and 35 (16: 32–33, with half the coarse
work of 8); the coarse corrections scaled by 1.5 or 2 (more iterations); ω = 0.55 and 0.85 (33
and 31 against 32). And the twicing's second solve started from 2s − f instead of s (the
first-order guess of S s): 55 iterations either way with Jacobi, more with the coarse levels.
In the library, runs of 32 for the first level: 31 + 23 iterations and the same time as 16
(1.58 / 1.66 s against 1.54 / 1.70 s, interleaved) with half the extra memory; 16 kept, as
calibrated. Also tried the same day on the quadric step, whose blend collects the two rings of
every vertex: the blend over the one ring only (the calibration set's geometric mean +6.8%,
0.000145786 and 0.000145128); the two rings collected with only the vertices that carry a
patch looked up (the same output bit for bit, the quadric step 3.21 / 2.88 s against 3.22 /
2.95 s: no gain, the walk over the graph's rows costs more than the set). Neither taken.

**Rings, patch coordinates and TV's gap checks (2026-12-07, second session).** A profile of
the quadric step on the noisy 1,000,000-point sphere (`perf`, scratch driver) showed three costs
that were not the arithmetic: collecting the rings in the hash set (probes and their
mispredicted branches, a third of the step), the ring covariance, whose running sums lived in
the object's members and went through memory at every point (they may alias the points), and
the patch's second tangential axis n × u, built as a vector on the stack and read back as a
pair (a stalled store at every patch the blend evaluates). Now the rings are marked in a window
of direct stamps that follows the Morton-ordered vertices (131,072 of them, 512 KB; at 1M points
99% of the two-hop entries lie within 65,536 positions), one load and one store each and no
branch on the data, with the hash set only for the members outside it
(`src/core/two_ring.h`); the covariance is summed in locals; the coordinates are written in
scalars, the same products summed in the same order. The output is the same bit for bit
(the 1M sphere's quadric step: mean distance 0.000444419, checksum unchanged), and
`TwoRing.TheDirectWindowAndTheHashSetCollectTheSameRings` checks that windows from one vertex
to the whole graph give the same rings in the same order. Collecting every vertex's two rings
and 40% of them three took 1.58 s on one thread with the hash set, 0.6–0.8 s with the window.
The quadric step (two threads, old and new library interleaved, a session with a large spread):
2.95–3.55 s → 1.6–2.2 s. Tried with them and not kept: the quadric's 21 moment sums split into
three passes that keep them in registers (one pass spills them; the same sums bit for bit, no
gain outside the spread), and the fit's running patch support kept in a local (likewise).
TV's duality gap was checked every 10 iterations, so a solve stopped up to 9 iterations after
it met its tolerance (the 1M sphere's solve at 10⁻² met it at iteration 41 and ran to 50). Now
it is checked after 5 and 10 iterations and then when the rate of fall between the last two
checks would bring it to the tolerance (one iteration on at the least, 10 at the most): about as
many checks (one more), and the stop within about an iteration of the tolerance
(`TotalVariationSolver.StopsWithinAnIterationOfMeetingItsTolerance` finds that iteration by
capping solves and holds the stop to it or the next). On the calibration set kept apart
(`calibrate_gamma --default-only --no-risk`, 96 clouds) TV's geometric mean went from
0.000137875 to 0.000137641 (−0.17%; every cloud within −1.7% and +0.6%), Tikhonov's unchanged
(0.00013649, bit for bit). `build/bench/bench_smoothing 1000000` after the three changes:
sphere Tikhonov 4.50 s (5.87 s in the session before), TV 7.28 s (8.65), the graph build 0.90
s: 5.03 × and 8.14 × it (were 6.14 × and 9.04 ×; targets 2 × and 6 ×); cube Tikhonov 4.98 s
(5.15), TV 7.77 s (7.82), graph 0.90 s (0.67 in the session before): 5.52 × and 8.62 ×; against
MLS at its most accurate radius Tikhonov takes 0.19 × and 0.24 × its time, TV 0.30 × and 0.38
×, against jet smoothing 0.36 × / 0.45 × and 0.59 × / 0.70 ×; errors unchanged (0.00044,
0.00087, 0.00091, 0.00105). `bench_memory 1000000`: Tikhonov 396.0 bytes per point (395.3),
TV 537.1 (535.4), the chain outliers → TV 529.5 (527.9) in 10.35 s, 0.41 × the PCL chain's
time. TV's primal-dual iteration itself (about 50 ms at 1M points) is not bound by memory
bandwidth (about 45 GB/s here against the 10 GB/s it draws, and 100,000 points, whose arrays
fit in the cache, cost the same per entry): its largest part is gathering the neighbours'
coordinates of each entry (a quarter of the solve), then the projection and the adjoint. Tried
and not kept there: the duals stepped across row ends in full batches with the adjoint summed
two entries at a time in a second pass over the block's rows (no faster: 2.63–2.80 s against
2.65–2.78 s for one solve), and software prefetches of the neighbours' rows 8 to 64 entries
ahead (no gain).
With the stop now at the tolerance rather than at the next multiple of 10, TV's default
tolerance where quadrics are fitted (`GraphTVSmoothing::kFittedTolerance`) was tried looser on
the same calibration set, against 10⁻² with the new checks: 2 × 10⁻² geometric mean −0.09%
(0.000137522; every cloud within −1.8% and +1.2%, the CAD part-Lp gaining most), 3 × 10⁻²
−0.12% (0.000137478; but −2.4% to +2.9% on single clouds, the noisiest sphere losing most).
2 × 10⁻² is the default since (the full test suite passes with it unchanged but for the test
that names the default): the 1M sphere's TV solve at γ as derived 41 → 35 iterations, and the
TV filter with its defaults (scratch driver, interleaved) 90 → 75 primal-dual iterations in
7.03–7.68 s against 7.83–7.90 s, its error 0.0008742 → 0.0008644; on the 1M cube 83 → 70
iterations, error 0.0010573 → 0.0010561. (The bench_smoothing figures above are at 10⁻².)
`build/bench/bench_smoothing 1000000` again with it, in a slower stretch of the session (the
sphere's graph build 1.29 s against 0.90 s before): sphere Tikhonov 6.09 s, TV 9.24 s, 4.72 ×
and 7.17 × the graph build; cube Tikhonov 4.09 s, TV 6.19 s, graph 0.76 s, 5.38 × and 8.14 ×;
against MLS at its most accurate radius Tikhonov 0.27 × / 0.22 × its time, TV 0.41 × / 0.33 ×;
against jet smoothing 0.49 × / 0.38 × and 0.75 × / 0.57 ×; errors 0.00044, 0.00086, 0.00091,
0.00105.
Tikhonov's default tolerance where quadrics are fitted (`GraphTikhonovSmoothing::kFittedTolerance`,
10⁻⁴ since 2026-12-04, before the conjugate gradient had coarse levels) was tried looser the
same way: 2 × 10⁻⁴ geometric mean +0.006% (every cloud within ±0.5%), 5 × 10⁻⁴ −0.001%
(0.000136489 against 0.00013649; every cloud within −0.5% and +1.1%, the 50,000-point cube at
σ = 0.5% losing most). 5 × 10⁻⁴ is the default since: the Tikhonov filter with its defaults on
the 1M sphere (scratch driver, runs alternated) 50 → 37 conjugate-gradient iterations for the
twicing's two solves (44 at 2 × 10⁻⁴, 68 at the solver's own 10⁻⁵), 5.11–5.34 s → 4.43–5.04 s,
its error 0.0004433 → 0.0004446; on the 1M cube 35 → 25 iterations, error 0.0009157 →
0.0009168.

**TV's iteration in an AVX2 build (2026-12-07, third session).** An instruction count of TV's
solve (`valgrind --tool=callgrind`, 30,000 points, one thread) put about 58 instructions on each
entry and iteration: 12 to gather the neighbour's coordinates, 17 for the adjoint's sums
(a float-to-double conversion and a multiply per coordinate), and 19 for the dual step and its
projection, which the library's x86-64 baseline build (SSE2) runs four lanes at a time. Now the
dual pass takes the entries of a block in batches of 64 that run across row ends, weights the
duals by √w in the vectorised step, and sums each row's terms in double in entry order; and
the solver's loops (the dual pass, the primal step, the warm start and the total variation of
the gap checks) are compiled a second time for AVX2 and run in that build where the processor
has it (`src/core/wide_kernels.h`, `detail::wide`: always-inlined kernels in a function
compiled for the wider instruction set, chosen once by `__builtin_cpu_supports`). The two
builds give the same bits: every operation is the same IEEE operation in both (no contraction:
the file is compiled with `-ffp-contract=off`, and AVX2 alone has no fused multiply-add), which
`TotalVariation.TheAvx2BuildOfItsLoopsGivesTheSameBits` checks for both norms (it fails when the
kernels are allowed FMA). f's total variation, which decides between the warm and the cold
start, now comes with the warm start's pass (one pass fewer per solve). Time per entry and
iteration (`tvit`, a scratch driver: the solver alone at a fixed 30 iterations, best of
several): 30,000 points on one thread 5.9 ns → 5.8 ns with the batches alone → 4.7 ns with the
AVX2 build; 1,000,000 points on two threads 3.7 ns → 3.3 ns; the results change only in the
rounding of the adjoint's terms (now products in single precision): the 1M sphere's TV filter
keeps its 75 iterations and its error (0.0008699 in that driver), the calibration set's
geometric means are unchanged to six digits (Tikhonov 0.000136489, TV 0.000137522). The TV
filter on the 1M sphere (scratch driver, old and new library alternated) 6.37–6.43 s → 5.77–6.35
s. Also tried: the normals' and quadrics' file built for AVX2 (no gain: 1.69–1.76 s against
1.81–1.84 s for the quadric step; its sums are already in two-lane pairs), and the conjugate
gradient's loops through the same kernels (no gain: 3.67–3.80 s against 3.74–4.10 s for the
Tikhonov filter; its passes are bound by the gathers). `build/bench/bench_smoothing 1000000`
after the change: sphere Tikhonov 4.38 s, TV 5.83 s, the graph build 0.96 s: 4.56 × and 6.08 ×
it (targets 2 × and 6 ×); cube Tikhonov 3.62 s, TV 5.76 s, graph 0.70 s: 5.15 × and 8.19 ×;
against MLS at its most accurate radius Tikhonov 0.19 × / 0.20 × its time, TV 0.26 × / 0.32 ×;
against jet smoothing 0.40 × / 0.34 × and 0.54 × / 0.55 ×; errors 0.00044, 0.00086, 0.00091,
0.00105.
A gap check's total variation TV(x) took a pass over the graph of its own (gathering each
entry's two points again, a third of an iteration's time at 1M points, and a TV solve at the
filters' tolerance checks 5 or 6 times). Now the check takes its vertex terms (|x − f|²,
⟨f, ∇ᵀy⟩, |∇ᵀy|²) at once and TV(x) comes with the next iteration's dual pass, which gathers x
beside x̄ (x still holds the check's iterate there; the same sums in the same order as the
separate pass, so the same gaps, stops and results bit for bit); a solve that stops returns
that iterate, and the check at the iteration cap is still taken at once.
`TotalVariationSolver.StopsWithinAnIterationOfMeetingItsTolerance` fails when the fused sum is
off by 3%. The solver alone on the 1M sphere, 30 iterations with three such checks: 1.22–1.30 s
→ 1.12–1.30 s (`tvit`, best of 3, old and new library alternated); the TV filter's difference is
within the session's spread. `build/bench/bench_smoothing 1000000` after it: sphere Tikhonov
3.99 s, TV 6.22 s, the graph build 0.88 s: 4.52 × and 7.05 × it; cube Tikhonov 3.90 s, TV 5.93
s, graph 0.69 s: 5.63 × and 8.57 × (the same code's sphere was 6.08 × in the run before: the
ratios move by 15% between runs here); against MLS at its most accurate radius Tikhonov 0.17 × /
0.17 × its time, TV 0.27 × / 0.26 ×, against jet smoothing 0.35 × / 0.36 × and 0.55 × / 0.55 ×;
errors unchanged. `bench_memory 1000000`: TV 537.2 bytes per point, Tikhonov 400.3, the chain
outliers → TV 528.5 in 10.75 s, 0.48 × the PCL chain's time.

Twicing (`setShrinkageCorrection`, on by default) costs TV a second solve, about 1.6 s of the
1M filter's 5.8–6.3 s. Measured on the calibration set (`calibrate_gamma --no-twicing --no-risk
--multiples ...`, 96 clouds; the set's geometric mean error at each multiple of the derived γ):
without it TV's best constant multiple is about 0.35 (0.177: 0.000145249, 0.25: 0.000143324,
0.354: 0.000142554, 0.5: 0.000144109, 1: 0.000161264), still 3.7% above the default with
twicing (0.000137522); Tikhonov's best, 0.000146211 at 0.177, is 7.1% above its default
(0.000136489). On the 1M sphere and cube (scratch driver, γ as derived) TV without twicing took
4.50 s and 4.22 s against 6.13 s and 5.73 s, with errors 0.0008202 and 0.0011544 against
0.0008699 and 0.0010539. Not taken: the time target would be within reach on both shapes, at
4% more error over the set. Two cheaper second solves were measured the same way
(`calibrate_gamma --default-only --no-risk`, a scratch build): the second solve from the cold
start (duals 0; 75 → 70 iterations on the 1M sphere) 0.000139259 (+1.3%), its tolerance 1.5
times looser 0.000137656 (+0.1%), both 0.00013977 (+1.6%): not taken.

**Twicing's two Tikhonov solves on one system; the graph's components in parallel (2026-12-07,
fourth session).** Each Tikhonov solve set up its system anew: the weighted degrees, the
conjugate gradient's coarse levels (`AggregationPreconditioner`) and the graph's connected
components (for the stopping test's scale), about 0.12 s at 1,000,000 points, and twicing
solves twice on the same graph and γ. `core::TikhonovSystem` now holds that set-up (with
CHOLMOD: the factorisation) and solves any number of signals; `solveTikhonov` is one system
solved once, and the filters ask their subclass for a `smoother (graph, γ)` that twicing's two
solves share (released before the local surface is fitted). The output is the same bit for bit
(`calibrate_gamma --default-only --no-risk`: every cloud's error identical; Tikhonov
0.000136489, TV 0.000137522); `TikhonovSystem.SolvesEverySignalAsAFreshSystemWould...` checks
that a solve leaves nothing in the system and that two solves are the squared spectral filter,
with the conjugate gradient and with CHOLMOD. The connected components (union-find over the
graph's entries, 52 ms at 1M points, once per filter pass and once per Tikhonov solve before,
once per Tikhonov system now) join
each edge once, from the row of its smaller vertex, in blocks of 65,536 consecutive vertices on
the threads, the edges between blocks joined afterwards (35 ms; the
labels are each component's smallest vertex whatever the order of the joins;
`Components.MatchABreadthFirstSearchOnAnyNumberOfThreads` has components across blocks,
zero-weight entries that must join nothing, and rows out of order). Twicing's two solves on the 1M sphere and cube
(scratch driver, γ as the filter derives it, tolerance 5 × 10⁻⁴, best of 3, old and new library
alternated, three rounds): sphere 1.38–1.74 s → 1.18–1.48 s, cube 1.06–1.41 s → 0.91–1.23 s;
with CHOLMOD (200,000 points) 6.43 s → 3.20 s (sphere) and 5.55 s → 2.78 s (cube).
`build/bench/bench_smoothing 1000000` after both: sphere Tikhonov 6.20 s, TV 10.00 s, the graph
build 1.375 s: 4.51 × and 7.27 × it; cube Tikhonov 5.72 s, TV 8.75 s, graph 1.02 s: 5.59 × and
8.55 ×; against MLS at its most accurate radius Tikhonov 0.23 × / 0.28 × its time, TV 0.37 × /
0.43 ×, against jet smoothing 0.41 × / 0.41 × and 0.66 × / 0.62 ×; errors unchanged (0.00044,
0.00086, 0.00091, 0.00105). Every time in that run is 20–60% above the previous session's on
this machine (MLS at 3 × d20 27.1 s against about 23 s; the k-NN graph 1.0–1.4 s against 0.7–0.9
s), the two-threaded parts the most, so its ratios against the single-threaded peers are not
comparable with the earlier runs'. The same session's scratch driver, core steps with the old
and new library alternated, found no step slower (TV's solves 2.08–2.25 s and 1.97–2.43 s with
either library, the quadric step 2.05–2.52 s).
Tried the same session and not taken: the blend over each point's own ring instead of its two
rings (the quadric step 2.06–2.10 s → 1.62–1.78 s on the 1M sphere, but the calibration set's
error +6.8% for Tikhonov and +5.2% for TV: at a cover of 3 the one ring holds too few
patches); accepting a robust quadric fit after its first fit (weighted from the plane through
the point) when it lies within one noise level of that plane at every ring point (the quadric
step 2.17 → 1.69–1.74 s; the set's geometric mean −0.72% and −0.58%, but single clouds from
−16% (the casting) to +13% (the CAD parts at 50,000 points and 3%): a different estimator, not
an early stop; at half a noise level the step gained 6%); starting twicing's second
conjugate-gradient solve from 2 x₁ − f instead of x₁, which first-order expansion suggests (14
→ 21 iterations on the 1M sphere, 10 → 14 on the cube: its residual (2γL)² x₁ is larger on the
high frequencies that the first solve left).

**TV's x-bar in single precision; twicing's two TV solves on one system (2026-12-07, fifth
session).** A profile of the TV dual pass at 1,000,000 points (`perf record`, the solver alone)
put its largest stall on the gather of each entry's neighbour in x-bar, the extrapolated
iterate (24 bytes per vertex in double; 1 thread took 75–81 ms per iteration, 2 threads 37–43
ms, so the pass is bound by that latency rather than by the threads). x-bar only feeds the
dual step's differences, which were already rounded to single precision: it is now stored in
single precision, about the position of its component's root (the component's smallest
vertex), so that coordinates far from the origin, or one point far from the rest, keep their
differences (the first version took f's mean as the origin and failed
`SmoothingQuality.AFarPointLeavesTheRestAsItWas`: a point at 10⁹ pulled the plane's mean to
10⁶); the iterate, the objective and the gap stay in double. Single precision puts a floor
under the duality gap (on a 20,000-point sphere at 8 × TV's rule the gap stalled at 3 × 10⁻⁶,
where double reaches 10⁻⁸; the clean-clone CI caught it as one test solving to 10⁻⁶ that ran
its 100,000-iteration cap in 92 s, 517 s under the sanitizers), so x-bar is kept in double when
the tolerance is below ten times the rounding 2⁻²⁴ R / L of a difference (R the farthest
coordinate from its origin, L the entries' mean length weighted by √w; 3.2 × 10⁻⁶ on that
sphere, where the gap stalled, 1.3 × 10⁻⁵ on the 1M sphere, far below the filters' 2 × 10⁻²); at 10⁻⁵ and tighter that
sphere's solves now take the iterations they took before (140, 230, 421 at 10⁻⁵, 10⁻⁶, 10⁻⁷).
Per iteration on the 1M sphere
(γ 0.05658 as the filter derives it, 35 iterations, scratch driver, old and new library
alternated): 2 threads 43.1 / 42.4 → 38.5 / 37.0 ms, 1 thread 80.9 / 79.1 → 73.7 / 71.1 ms; the
calibration set is unchanged to six digits (Tikhonov 0.000136489, TV 0.000137522).
`TotalVariationSolver.ASignalFarFromTheOriginIsSolvedAsWellAsNearIt` shifts a signal by 10⁶, and
one of two spheres in one graph by 10⁶ (it fails with one origin for all). Then
`core::TotalVariationSystem`, as `TikhonovSystem`: the entries' √w, the vertices' steps and the
components set up once, and the duals (12 bytes per entry) and two vertex arrays allocated by
the first solve and kept, so that twicing's second solve neither recomputes nor faults them in
again; the same bits as a fresh solve (`TotalVariationSystem.SolvesEverySignalAsAFreshSystemWould`,
also across a cold and a warm start). Two solves on the 1M sphere at the filter's γ and
tolerance: 2.84 s → 2.72–2.83 s (within the noise of the measurement, about 4% at best).
Twicing's difference 2 x₁ − S(x₁) is now formed in place, so the kept arrays add nothing to
the peak: `build/bench/bench_memory 1000000` TV 539.4 → 529.6 bytes per point (x-bar's 12 bytes
per point fewer), 6.76 s. `build/bench/bench_smoothing 1000000` after both: sphere Tikhonov
3.81 s, TV 5.90 s, the graph build 0.971 s: 3.92 × and 6.08 × it (the same binary's run before
the change: TV 5.96 s, graph 0.877 s, 6.80 ×: the graph build's own time moves the ratio by 10%
between runs); cube Tikhonov 3.36 s, TV 5.44 s (6.00 s before), graph 0.645 s: 5.20 × and 8.43
×; against MLS at its most accurate radius Tikhonov 0.21 × / 0.21 ×, TV 0.32 × / 0.34 ×;
against jet smoothing 0.40 × / 0.36 × and 0.62 × / 0.58 ×; errors unchanged (0.00044, 0.00086,
0.00091, 0.00105). Where the TV filter's time goes on the 1M sphere (scratch driver, the core
steps): graph 0.71 s, components 0.04 s, noise estimate 0.23 s, the two TV solves 3.0 s (35 + 40
iterations), the quadric step 1.55 s. Tried the same session and not kept: each row's adjoint
summed in four lanes by the entry's place in its row (the same bits for any batching; 75 → 81
ms per iteration on one thread: the lanes' loads and stores cost more than the chain they
break), software prefetches of x-bar 16 entries ahead (no gain, as in the session before), and
x-bar padded to four floats per vertex so that no row straddles a cache line (38.5–39.7 → 41.2
ms per iteration: a third more bytes to gather).

**One dual per edge in the TV solver; the graph build's time as the median of three (2026-12-07,
sixth session).** The duals lived on both stored entries of each edge, kept antisymmetric, so
that each row's adjoint read only its own entries: every edge was updated twice and its dual
stored twice. Now each undirected edge has one dual (the entries (i, j) of row i with j > i,
copied into a CSR of their own), and the adjoint is summed as the edges are updated, in fixed
blocks of 4,096 vertices in the Morton order (parallelSum's blocks, so the sums do not depend
on the number of threads): a row's own edges into its sum, the far end's share into that row's
sum to come when it lies in the block, else into a slot the primal step adds after the pass (7%
of the edges at a million points). A scratch prototype first measured the pass alone, 47 → 34.5
ms on two threads; in the solver the first version gathered the far blocks' duals by edge (four
cache misses each) and gained 8%, and with the terms written to consecutive slots during the
pass 13–14%: on the 1M sphere at the filter's γ (35 + 40 iterations, scratch driver, old and new
library alternated) 39.1–40.4 → 33.4–35.5 ms per iteration on two threads, 74.5–78.7 → 64.3–65.2
ms on one; the set-up of the system 0.064 → 0.096 s (the edges copied and the cross-block slots
listed, in parallel). The calibration set is unchanged to six digits (Tikhonov 0.000136489, TV
0.000137522), and so are the iterations (35 and 40). `TotalVariationSolver.TheVertexOrderDoesNotMoveTheMinimiser`
solves one graph in two vertex orders (other edges cross the blocks) and fails when the
cross-block terms are dropped. `build/bench/bench_memory 1000000`: TV 529.6 → 482.7 bytes per
point, the chain outliers → TV 529.2 → 472.5 (1.18 × the PCL chain's memory, 0.41 × its time).

`bench_smoothing` timed the graph build once, first in its process, and that first build takes
up to half as long again as the next (0.71–1.08 s on the 1M sphere): the ratios' denominator is
now the median of three builds. `build/bench/bench_smoothing 1000000` with both: sphere
Tikhonov 4.06 s, TV 5.53 s, the graph 0.724 s: 5.61 × and 7.63 ×; cube 3.66 s, 5.14 s, 0.692 s:
5.29 × and 7.43 × (the same binary with the first build as denominator had given 3.99 × and 5.47
× on the sphere, graph 1.079 s, and 5.15 × and 7.06 × on the cube). Against MLS at its most
accurate radius Tikhonov 0.19 × / 0.22 ×, TV 0.26 × / 0.31 ×; against jet smoothing 0.41 × /
0.37 × and 0.55 × / 0.53 ×; errors unchanged (0.00044, 0.00086, 0.00091, 0.00105). The earlier
ratios of this report (6.08 ×, 8.43 × and the like) used the first build and are flattered by
as much.

**Noise of several spacings; the quadric fits' weights in AVX2 kernels (2026-12-07, seventh
session).** A helper measured the defaults against the peers with noise of 1 to 8 point
spacings (σ / s, s = √(area / n)), beyond the calibration set's range (up to about 2): the unit
sphere, the cube, the Stanford bunny and fandisk (normalised to the unit sphere), 20,000,
50,000 and 100,000 points, one thread; peers MLS (order 2, the best of 3, 5, 8 × the mean
10-NN distance per cloud, chosen against the truth), jet smoothing (k 18 and 48) and bilateral
smoothing (k 24, sharpness 25, 3 iterations); error the mean distance to the true surface. Up
to 4 spacings the defaults led as on the calibration set (but for the sphere at 1 spacing,
where MLS at its widest radius wins, and fandisk at 4: +3–10%). At 6 and 8 spacings Tikhonov
lost every case (by 7–250%; on the 20,000-point sphere at 6 spacings its output was worse than
its input), and TV lost 11 of 12 at 8 spacings. Three causes, three changes:

- *The bending read as "not measured".* Where the noise buries the surface's bending, every
  ball of the detail term is no thicker than the noise and `NoiseEstimate::curvature` read 0,
  which also meant "not measured" and gave a detail term of 1 instead of the limit of a
  vanishing bending, 16: γ 16 times too small. Not measured is now −1, and 0 gives 16. A
  50,000-point sphere at 8% noise (about 5 spacings): Tikhonov 0.0289 → 0.0142, TV 0.0352 →
  0.0097 (input 0.0643; `SmoothingQuality.NoiseOfSeveralSpacingsStillGetsTheFullDetailTerm`);
  1,000,000 points at 2% (5.6 spacings): Tikhonov 0.0066 → 0.0010, TV 0.0083 → 0.0018.
- *The noise estimate pinned.* The spacing is counted in a ball of 4 mean 10-NN distances,
  whose count model π (R² − 1.45 σ̂²) fails once the noise nears the ball: on the noise table's
  160,000-point planes the level read 18% high at 6 spacings and stuck at the table's last row
  (8 spacings) beyond, so that σ̂ / ŝ read 8 at 6 and at 8 (σ̂ 12–16% high at 6, 5–15% low at
  8, in the helper's clouds). The ball is now widened, twice as wide at most twice, while the
  solved level exceeds 0.45 of its radius, and the table runs to 16 spacings: on those planes
  the level within 5% up to 8 spacings (0.969 at 6, 0.947 at 8), 0.908 at 10 and 0.811 at 16
  (`build/bench/calibrate_gamma --noise-table`; `NoiseLevel.RecoversNoiseOfSeveralSpacings`).
  No cloud of the calibration set widens its ball.
- *The rules past their range.* With the noise read right, a sweep of the defaults at ¼–4 × γ
  (20,000 and 100,000 points, 4–8 spacings) put TV's best multiple at 1.4–4 and Tikhonov's at
  0.25–1 (mostly 0.5 at 8 spacings). Of the schedules max(1, r / r₀)^p tried on that sweep (r =
  σ̂ / ŝ, the surface spacing counted in the ball, not the k-NN distance, which grows with the
  noise; r₀ 2, 2.5, 3, 4; p ½, ¾, 1, 1½), r₀ = 4 and p = 1 (TV ×, Tikhonov ÷) lost least in the
  worst cloud (1.14 and 1.13 × the untouched rule's error) for geometric means 0.927 and
  0.939, and leaves the calibrated range alone (`core::highNoiseGammaFactor`, applied on top of
  the refined terms and beyond their bounds). Checked on the held-out 50,000-point clouds: the
  two changes together against the rules before (with the detail term's fix) geometric mean
  × 0.840 (Tikhonov) and × 0.953 (TV), TV losing at 6 spacings on the cube and the bunny (+6%)
  and fandisk (+20%) and gaining 12–55% at 8. On the calibration set one cloud reaches r > 4,
  the 50,000-point casting at 3%: Tikhonov −2.1%, TV +3.6% (set geometric means 0.000136489 →
  0.000136459 and 0.000137522 → 0.000137573).

Against the best peer over the helper's 40 clouds at 20,000 and 100,000 points (1–8 spacings):
Tikhonov now ahead in 24 (geometric mean 0.969 × the best peer's error, 1.121 before these
changes), TV in 31 (0.871, 0.915 before). Where they still lose it is at 8 spacings (Tikhonov
1.15–1.34 ×, TV up to 1.17 ×, against MLS at the radius the truth picks) and on the 20,000-point
sphere (Tikhonov 1.19–1.85 ×). Command: `build/bench/bench_high_noise` (those 40 clouds, the
filters with their defaults and the peers side by side, and the counts and geometric means
above; `--sizes 50000` the held-out ones). The γ sweeps and the A/B runs of the two changes
were scratch drivers over the same clouds.

Tried the same session and not taken: twicing's second TV solve started from the duals the
first left (a system option, `TotalVariationStart::LAST_DUALS`, implemented and tested, then
reverted). On the 1M sphere it cut the TV filter's iterations from 35 + 40 to 35 + 29 (about
0.35 s, 7% of the filter) and on the calibration set it moved nothing (geometric mean
0.000137522 → 0.000137526, single clouds −1.5% to +3.4%; in the session of 2026-12-04 the same
idea had cost 0.5% on the 1M sphere at 10⁻²), but on the helper's high-noise clouds it cost
1.8% in geometric mean and up to 16% (the 20,000-point sphere at 4 spacings): at strong γ the
first solve's duals overshoot the second problem's and the stop at 2 × 10⁻² keeps part of it.

The quadric step's robust weights exp(−t² / 2) and the blend's weights now come from an exp
written as plain arithmetic (`detail::expOfNonPositive` in `src/core/wide_kernels.h`: Cody and
Waite's reduction, the degree-13 Taylor polynomial, 2^k into the exponent's bits; within 5 ×
10⁻¹⁶ of `std::exp`, 0 below −708), and the normal equations' 21 moments are summed in four
lanes; both loops are kernels that run in the AVX2 build where the processor has it (the same
bits either way: `Normals.TheKernelsExpMatchesTheLibrarysAndTheAvx2BuildTheBaseline`). Eigen's
vectorised exp took 4.7 ns per value here (SSE2), the kernel's 1.5 ns in AVX2. The quadric step
on the 1M sphere (scratch drivers, old and new library alternated): 1.53–1.65 s → 1.44–1.54 s
within the filter, 2.22–2.33 s → 1.98–2.06 s at a stronger γ; the calibration set unchanged to
six digits.

**The sampling density divided out of the weights (2026-12-08).** A probe of inputs the
suite lacks (a helper's scratch driver; 40,000-point clouds of the kitten, the bunny, a ground
plane, planes and spheres; the peers at their best setting per cloud, as in section 2) found
the defaults behind where the sampling density or the noise varies across a cloud: noise along
the viewing ray growing with the squared depth (the kitten 1.39 × the best peer's error, its
far half 2.32 ×; the bunny 1.25 ×), a ground plane seen at a grazing angle with a camera's
density (3.42 ×, its far part 13 ×), and on planes and spheres whose density falls 10–30-fold
the sparse half kept 1.4–1.9 times the dense half's error. On the Gaussian weights a vertex's
degree grows with the density, and with it how much the Laplacian smooths it: sparse parts
keep their noise. The filters now divide the density out (`core::normalizeDensity`,
`setDensityNormalization`, on by default with normal displacement; the paper's filters keep
its weights): w_ij a_i a_j with a_i = (d̄ / d_i)^p, d̄ / d_i clamped to 1/16–16, which with
p = 1 is Coifman and Lafon's normalisation with α = 1 ("Diffusion maps", 2006): a vertex is
smoothed the more the lower its degree was. The γ rule still reads the Gaussian weights'
degrees. On the calibration set (`calibrate_gamma --default-only --no-risk`, 96 evenly sampled
clouds, where it evens out the random variation of the degrees and pulls in the points that
noise carried away from their neighbours; a scratch build with p and the clamp as settings)
p = 0.25 / 0.5 / 0.75 (these three without the clamp) / 1 / 1.25 / 1.5 gave Tikhonov 0.0001343 / 0.0001322 / 0.0001307 /
0.0001302 / 0.0001305 / 0.0001325 and TV 0.0001360 / 0.0001343 / 0.0001328 / 0.0001317 /
0.0001310 / 0.0001316, from 0.000136459 and 0.000137573 (without the clamp, from p = 1.5 a
few weights grew without bound and TV lost its precision); p = 1 with the clamp at 4,
0.0001304 / 0.0001321. The rule's best constant multiple stayed at 1 for Tikhonov (the sweep
½, 0.71, 1, 1.41, 2: 0.0001358, 0.0001322, 0.0001302, 0.0001310, 0.0001365) and moved to
about 1.4 for TV (0.0001311 against 0.0001317 at 1; not re-tuned). Noise of several spacings
needed a limit: on a sphere of 50,000 points at 6% and 8% noise (3.8 and 5 spacings)
Tikhonov's error went 0.0053 → 0.0121 and 0.0087 → 0.0196. Its rule sits just below the
strength at which the twicing and the quadrics collapse the surface (× 2: 0.023 and 0.034),
and the divided-out degrees, which there measure the noise's scatter rather than the
sampling, moved that edge below the rule (best multiple ½); keeping the mean degree, p = ½, or
a clamp at 2 or 4 did not avoid it. So the power fades from 1 at 2.5 spacings of noise to 0 at
3.5 (`core::densityNormalizationPower`, the ratio σ̂ / s̃ of the high-noise factor; fades
from 2 / 3 to 3 / 4 were also measured: 0.0001308 / 0.0001325 and 0.0001304 / 0.0001319).
With it: the calibration set 0.000130418 (−4.4%, Tikhonov) and 0.000132034 (−4.0%, TV); the
spheres of 20,000 and 50,000 points at 1–8% noise no worse than before at any level
(Tikhonov at 20,000 points 0.00134 → 0.00128 at 1%, 0.00465 → 0.00414 at 6%; at 50,000 and
6–8% unchanged); the 1,000,000-point sphere of `bench_smoothing` (σ = 1%, 2.7 spacings,
power 0.76) Tikhonov 0.0004438 → 0.0003907 (45 iterations instead of 36; the filter 4.0–4.3
s as before) and TV 0.0008599 → 0.0008289; `build/bench/bench_smoothing 1000000` after it:
sphere Tikhonov 4.24 s and 0.00039, TV 5.31 s and 0.00083, the graph 0.746 s (5.68 × and
7.11 × it; were 5.70 × and 7.45 ×); cube Tikhonov 4.02 s and 0.00087 (0.00091), TV 5.04 s and
0.00099 (0.00105), the graph 0.722 s (5.58 × and 6.99 ×); MLS at its most accurate radius
0.00086 and 0.00113 in 22.6 s and 17.5 s. `bench_memory 1000000`: Tikhonov 407.4 bytes per
point, TV 482.6 (406.6 and 482.7 before). The probe again, ours over the best peer
(Tikhonov; TV): the kitten with ray noise growing with depth 1.39 → 1.10 (1.62 → 1.54), the
bunny 1.25 → 1.03 (1.36 → 1.32), with constant ray noise 1.02 → 0.91 and 0.92 → 0.84, with
isotropic noise growing with depth 0.97 → 0.89 and 0.82 → 0.75; the grazing ground plane with
a camera's density 3.42 → 1.95 (3.47 → 2.37), with an even density 1.75 → 1.69; but with a
camera's density on the two meshes 1.10 → 1.14 and 1.00 → 1.03. Planes and spheres whose
density falls 1–30-fold: Tikhonov's error lower in 9 of 12 (the planes by 8–17%), the same
in one, and 3% and 6% higher on the sphere at 30-fold; a thin box whose walls are 4σ apart 1.56 → 1.69 (the two sheets
were already pulled together: below). The square of
`SmoothingQuality.DensityNormalizationSmoothsSparsePartsAsWellAsDenseOnes` (20,000 points,
density falling 30-fold, σ = 0.01): Tikhonov's sparse half 0.001364 → 0.000789 and its dense
half 0.000815 → 0.000786; TV 0.001428 → 0.001295 and 0.001119 → 0.001095. What the probe
still finds, and this change does not touch: two sheets 3–4σ apart are read as one thick sheet
(σ̂ 0.0169 against 0.010) and pulled together (two planes at a gap of 3σ: 2.15 × the best
peer, worse than the input); clouds of 500–1,000 points on detailed meshes read their bending
as noise (σ̂ 3–5 × the truth at 500 points) and lose 1.1–1.5 × to jet; and on planes and
spheres MLS at 8 mean 10-NN distances, chosen by the truth, stays 1.2–2.1 × ahead.

**Two TV dual-pass trials, not taken (2026-12-08).** The dual pass, a third of the TV filter's
time at 1,000,000 points, was thought bound by memory traffic. Duals stored in 16-bit fixed
point (steps of γ / 32767; 6 bytes per edge instead of 12): the same iterations and error
(0.0008599), but the pass's share of the samples grew (31.6% → 34.0%, `perf`): it waits on
the gather of the neighbours' x-bar, not on the duals. Prefetching the next batch's
neighbours' x-bar: three solves in 6.466 s against 6.462 s. (Both measured with another job
running: shares and alternated runs, not absolute times.)

The tables of sections 2, 3 and 6 were not regenerated for the 2026-12-07 sessions' changes nor for
the density normalisation above (which moves the calibration set by −4.4% and −4.0%); by the
calibration set they move TV's errors by −0.22% (geometric mean 0.000137875 → 0.000137573; single clouds −1.9% to +1.7%, and
+3.6% more on the 50,000-point casting at 3% from the high-noise factor above); Tikhonov's by −0.02% (0.00013649 →
0.000136459; single clouds −0.5% to +1.1%, and −2.1% on that casting).

## 6. Time-varying clouds

`GraphSequenceSmoothing` denoises each frame on the paper's spatio-temporal graph (k1 = 10
neighbours in the frame, k2 = 3 in each of frames t − 1 and t + 1), with the static filters'
smoothing and refinements (`build/bench/evaluate sequences`, about 40 minutes); the temporal
columns run it with motion compensation (`setMotionCompensation (true)`: the other frames
moved onto frame t's surface first, README *Sequences*), the *uncompensated* column with its
default, the paper's graph on the frames as they are. Synthetic
sequences: a cube [−1,1]³ turning and sliding (speed 1: 1.5° about z and 0.01 along x per
frame, up to 0.045 at the corners), the unit sphere turning 2° per frame about (1, 1, 0) (its
surface maps onto itself), and a plane waving as z = 0.1 sin 2π(x − t/20) (its crest moves up
to 0.031 per frame); speed 0.25 runs the same motions four times slower.

TAIL
  cat "$results/sequences.md"
  cat <<'TAIL'

![The fixed Kinect's middle frame, coloured by the distance of each point to the next frame's surface](kinect_temporal.png)

What the numbers say:

- With motion compensation the temporal filter lowers the error against the static filter
  frame by frame, at the same γ, by 27–33% on the moving cube, 39–40% on the rotating sphere
  and 36–41% on the waving plane, at both speeds, every noise level and with both filters:
  the issue's target (25% on every sequence) holds, as it does with each filter at its own
  defaults (27–29% on the cube, at least 27% everywhere) and at its own best γ (at least
  27%). With the detail term alone it had slipped at the same γ for TV on the cube (23–25%:
  the static γ both runs share is the frame's, and the detail term raised it on the cube's
  flat faces); TV's noise term of section 5 lowers it there (σ̂ is below half a spacing) and
  the cube gained 31–32% again (31–33% now).
- The adaptive quadric support of section 5 (the default since 2026-12-04, measured then)
  lowers both columns on every sequence: against the run before it, over two
  rings, the static filter's error by 0.80 × and the temporal filter's by 0.82 × (geometric
  means over the 36 rows at the defaults); the gains over the static filter are therefore a
  little smaller on the sphere (37–44% before). Its time: the speed table (whose figures do not
  compare with the previous run's, section 5).
- Without it (the paper's graph, the default) the gain depends on how far the surface moves
  between frames against the noise: the sphere, whose surface stays in place, gains as much
  (40–41%), but at speed 1 the temporal links average surfaces that are no longer in the same
  place and the error rises (cube down to −34%, plane down to −270%; with the own quadric, the
  default before the blended quadrics of section 5, −56% and −299%).
- How the compensation was reached (one-off runs with the own quadric, on these sequences, 20 frames of 5,000
  points, Tikhonov at the derived γ of frame 0; gain over frame by frame for the plane at
  speed 0.25 and σ = 0.5%, the sphere at speed 1 and σ = 1%, the plane at speed 1 and σ = 1%,
  the cube at speed 1 and σ = 0.5%): none +5 / +42 / −97 / −47%; each other frame's points
  moved along the pooled normal of their 30 nearest points in both frames by the offset
  between the two centroids, +25 / +24 / +26 / +3% (the offsets' own noise, 0.26σ, spoils the
  still sphere); offsets shrunk by 2 standard errors (soft threshold) +22 / +41 / +10 / +10%
  (the shrinkage biases real motion); non-negative garrote at 2 standard errors instead,
  +22 / +41 / +21 / +12%; then averaged over the 30 neighbours, +27 / +41 / +24 / +9%; with a
  robust point-to-plane rigid fit of the offsets first (5 rounds), +41 / +41 / +42 / +29%,
  taken. The cube's faces were the hard part: near its edges the local offsets mix two
  faces, which the rigid fit does not. The waving plane's wave travels along x, so a
  translation maps each frame onto the next up to its ends and the rigid fit finds it; a
  deformation that no rigid motion explains is left to the offsets along the normals (a
  sphere grown by 4%, 5σ, comes back to within 1.2× the noise: test
  `SurfaceOffsets.FollowADeformationThatNoRigidMotionExplains`). An earlier attempt with the
  raw centroid offsets and k = 30–300 (no significance test, no rigid fit) was worse
  everywhere but on the waving plane at speed 1.
- Frames of different densities and sharp edges (fixed 2026-12-06; the table above is of the
  fixed code): each frame's 30 nearest points were compared, and on a curved surface the mean
  of a wider disk lies further below it, so the density difference read as an offset. A still unit sphere (σ = 1%)
  in frames of 1,000 / 4,000 / 1,000 points came out at 0.0159 / 0.0044 / 0.0166 (input
  0.0078, paper's graph 0.0009 / 0.0007 / 0.0008, 2,000 / 4,000 / 2,000 points already 0.0030
  / 0.0014 / 0.0027). The first fix compared both frames over one disk, measured across the normal
  (the moving point's 30 nearest, or the reference's 60 nearest where those reach less far),
  and each principal direction of the rigid fit is shrunk like the offsets (garrote at 2
  standard errors; directions a hundred times less constrained than the best get none): 0.0010
  / 0.0008 / 0.0011, and at 500 / 5,000 / 500 0.0011 / 0.0009 / 0.0008 (was 0.043 / 0.0066 /
  0.044); a turning and sliding cube in frames of 1,250 / 5,000 / 1,250 / 5,000 points
  0.0019–0.0025 against 0.0025–0.0057 frame by frame. That first fix took the moving frame's
  points from its 30 nearest and the reference's from its 60 nearest within the disk's
  cylinder: at a sharp edge the cylinder takes in points of the other face beyond the 30
  nearest, for the reference only, and a still cube in two 5,000-point frames (σ = 0.5%) read
  0.0023–0.0029 of offset near its edges; this table's moving cube fell from 26–32% to 23–30%
  (a first regeneration, stopped). Now both frames' points come from their 60 nearest, within
  the same cylinder and one ball that both sets cover (around the point for the moving frame,
  around it moved by the two neighbourhoods' offset for the reference, so that a surface
  further away than the disk is still measured): the still cube 0.0003–0.0010, the moving
  cube 27–33% (table above), the still sphere of 1,000 / 4,000 / 1,000 points unchanged
  (0.00097 / 0.00076 / 0.00107), and at 100 / 20,000 / 100 points the first frame 0.0007
  (was 0.0036; paper's graph 0.0007). Its cost: the moving frame's 60 nearest are searched
  as well, temporal filtering with motion compensation at 100,000 points went from 5.35 × to
  6.23 × the static filter's time (Tikhonov) and from 4.08 × to 5.97 × (TV) (speed table
  above; the run before was on another machine). Tests
  `SurfaceOffsets.LeaveASurfaceSampledAtAnotherDensityWhereItIs`,
  `SurfaceOffsets.LeaveAStillCubeWhereItIsAtItsEdges`,
  `SurfaceOffsets.MeasureAnOffsetLargerThanTheNeighbourhood`,
  `SequenceSmoothing.MotionCompensationKeepsAStillSceneOfFramesOfDifferentDensities`.
- Why it is not the default: on a still scene seen by a real sensor it cannot tell the
  sensor's frame-to-frame correlated noise (the Kinect's depth quantisation and drift) from
  motion. On the fixed Kinect the rigid fit found a 12 mm slide along the dominant planes
  (where nothing constrains it but that noise) and the local offsets a median 1.6 mm, and
  the compensated filter keeps what the default averages away (table above). Turn it on for
  surfaces that move between frames by more than about the noise.
- Also tried and not taken: the noise level estimated on the centre frame alone (the
  quadric's robust scale) instead of on the spatio-temporal graph: cube at speed 0.25 9% → 6%,
  the rest equal or worse; and bilateral temporal links, each edge between frames weighted by
  exp(−((nᵢ·d)² + (nⱼ·d)²) / (4c²σ̂²)) with d the edge and n the normals, c = 1, 2, 4 (quick
  subset, Tikhonov, σ = 1%): the cube at speed 0.25 gains (9% → 17%, 13%, 11%), the sphere and
  the plane lose (38% → 35–37%; plane 23% → 19–23%, at speed 1 −111% → −127% to −112%) (both
  measured without motion compensation). For a moving sensor, register the frames first
  (`examples/sequence_registration.cpp`, PCL's ICP).
- Time per frame: see the speed table; each frame is solved on the graph of its three-frame
  window, which is what makes the streaming result equal the batch one, and the compensation
  adds the offsets of the two other frames.
- The fixed Kinect: the static filter frame by frame leaves consecutive frames slightly further
  apart than they came (median 3.59 → 3.85 mm: each frame is smoothed towards its own
  surface), the temporal filter brings them to 1.92 mm (TV 1.85 mm; TV at its solver's own
  tolerance, before section 5's looser default, 1.78 mm; over two rings 1.93 and 1.80 mm; with
  the blended quadrics before the detail term 1.64 and 1.59 mm), at 5.8× the time for Tikhonov.
  Leaving out of the graph the links whose weight underflows to 0 and the isolated far points
  out of the spacing (robustness fixes, [reliability](reliability.md) fix 9) moved these
  temporal rows by at most 0.7% (TV's mean 3.107 → 3.129 mm, median 1.847 → 1.849 mm) and no
  other figure of this report.
  TV converges with the preconditioned solver of section 5 (with the detail term
  alone and the previous solver it stopped at its limit of 500 iterations).

## Not yet in this report

WLOP at 50,000 points (`PGD_WLOP=1` with the 50,000-point sizes; at 10,000 points see section 2),
and CGAL `remove_outliers` on the real clouds beyond the count of points removed.
`ctest -R evaluation_quick` re-checks the claims stated as holding on the quick subsets.
TAIL
} > docs/evaluation.md
echo "wrote docs/evaluation.md, docs/figure3.png and docs/bunny_bun000.png"
