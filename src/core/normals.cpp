/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/normals.h>

#include "huge_pages.h"
#include "neighbor_search.h"
#include "parallel.h"
#include "spatial_order.h"
#include "two_ring.h"
#include "wide_kernels.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>

#include <stdexcept>
#include <vector>

namespace pcl_graph_denoise {
namespace core {

Signal3
estimateNormals (const PointGraph &graph, const Signal3 &points, int num_threads)
{
  const std::size_t n = graph.numVertices ();
  if (static_cast<std::size_t> (points.rows ()) != n)
    throw std::invalid_argument ("estimateNormals: points of the wrong size");
  Signal3 normals = Signal3::Zero (static_cast<Eigen::Index> (n), 3);
  detail::parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    std::vector<VertexIndex> ring;
    detail::TwoRing two_ring;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    for (std::size_t i = begin; i < end; ++i)
    {
      two_ring.collect (graph, i, ring);
      if (ring.size () < 3)
        continue;
      eig.computeDirect (detail::ringCovariance (points, ring, i));
      normals.row (i) = eig.eigenvectors ().col (0).transpose ();
    }
  });
  return normals;
}

Signal3
normalDisplacement (const Signal3 &f, const Signal3 &x, const Signal3 &normals)
{
  if (x.rows () != f.rows () || normals.rows () != f.rows ())
    throw std::invalid_argument ("normalDisplacement: signals of different sizes");
  Signal3 out (f.rows (), 3);
  for (Eigen::Index i = 0; i < f.rows (); ++i)
    out.row (i) = f.row (i) + (x.row (i) - f.row (i)).dot (normals.row (i)) * normals.row (i);
  return out;
}

namespace {

constexpr std::size_t kQuadricMinimumRing = 10;  // 6 coefficients, with some redundancy
constexpr int kRobustIterations = 4;
/** The robust fit stops early once an iteration after the first moves the fitted surface
 *  by at most this many noise levels at every point of the ring: the next weights would
 *  differ by a few percent. On the calibration set (calibrate_gamma --default-only
 *  --no-risk, 96 clouds) 0.1 gave the same geometric-mean error as always four iterations
 *  (-0.09% Tikhonov, -0.07% TV, every cloud within 1.2%) in 18% less time for the fits of
 *  a 1M-point sphere; 0.3 lowered it by 0.7% and 0.5% but raised the noisy cubes' by up to
 *  2.3%. */
constexpr double kRobustStop = 0.1;
/** QuadricSupport::ADAPTIVE: the three-ring fit replaces the two-ring fit when the
 *  root-sum-square distance between their surfaces, under the two-ring points, is at
 *  most this many noise levels times sqrt(6) (this many standard errors per coefficient
 *  of a quadric). On the noisy sphere of Normals.AdaptiveSupport... 0.5 and 1 left more
 *  noise (2.7e-3 and 2.3e-3 against 1.9e-3); comparing only the fits' heights at the
 *  centre, within 2 of their standard errors, followed the corrugated sheet less
 *  (1.69e-3 against 1.52e-3). */
constexpr double kSupportAgreement = 2.0;
/** The three-ring fit is taken without the two-ring fit where it clearly agrees: the
 *  least-squares quadric of its residuals under the two-ring points (what a two-ring fit
 *  would add to it) moves them by at most this fraction of kSupportAgreement's bound (sum
 *  of squares). On smooth surfaces that spares nearly every two-ring fit (the quadric step
 *  of a noisy 1M-point sphere 3.1 s -> 2.6 s); elsewhere both are fitted and compared as
 *  before. On the calibration set (calibrate_gamma --default-only --no-risk, 96 clouds) 0.05
 *  moved every cloud by at most 0.4% (geometric mean +0.007% Tikhonov, -0.002% TV); 0.25
 *  by up to 4% (the casting), and 1 (the test alone) by up to 18%. */
constexpr double kClearAgreement = 0.05;
/** Blending: a patch's weight falls as exp(-d^2 / (2 (c r)^2)) with the point's
 *  tangential distance d from the patch's centre, r the patch's radius (the RMS
 *  tangential spread of its two rings, about the reach of its one ring at c = 1/2). */
constexpr double kBlendReach = 0.5;

/** The quadric's basis at tangential coordinates (a, b), already divided by the patch
 *  radius so that the normal equations stay well conditioned at any scale:
 *  (a^2, ab, b^2, a, b, 1). */
using Basis = Eigen::Matrix<double, 6, 1>;

/** The height q . basis(a, b), in scalars: a basis vector built on the stack and read
 *  back as pairs stalled the loads of the hot loops. */
inline double
quadricHeight (const Basis &q, double a, double b)
{
  return (q[0] * a + q[1] * b + q[3]) * a + (q[2] * b + q[4]) * b + q[5];
}

/** One vertex's local surface: a frame and the height field over it (17 doubles: a
 *  patch is kept for every vertex that carries one while the surfaces are blended). */
struct Patch
{
  Eigen::Vector3d origin = Eigen::Vector3d::Zero ();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero ();
  /** The first tangential axis divided by the patch radius (the second is normal x u);
   *  zero for a patch without extent. */
  Eigen::Vector3d u = Eigen::Vector3d::Zero ();
  /** Height coefficients over the basis; zero = the tangent plane through origin. */
  Basis q = Basis::Zero ();
  /** The largest squared (a^2 + b^2) of the points it was fitted to; negative: fewer
   *  than 3 points in the rings, no frame. */
  double support = -1.0;

  inline bool
  valid () const { return support >= 0.0; }

  /** Tangential coordinates of p. In scalars: the second axis normal x u built as a
   *  vector on the stack and read back as a pair stalled the blend's loop (the same
   *  sums, in the same order, as Eigen's dot and cross products). */
  inline void
  coordinates (const Eigen::Vector3d &p, double &a, double &b) const
  {
    const double d0 = p[0] - origin[0], d1 = p[1] - origin[1], d2 = p[2] - origin[2];
    a = (d0 * u[0] + d1 * u[1]) + d2 * u[2];
    const double v0 = normal[1] * u[2] - normal[2] * u[1];
    const double v1 = normal[2] * u[0] - normal[0] * u[2];
    const double v2 = normal[0] * u[1] - normal[1] * u[0];
    b = (d0 * v0 + d1 * v1) + d2 * v2;
  }

  /** The height of the surface above (a, b), pulled back onto the fitted extent when
   *  (a, b) lies outside: a patch much smaller than a point's distance from it (the
   *  points of a piecewise-constant TV estimate, collapsed together) must not be
   *  extrapolated. */
  inline double
  height (double a, double b) const
  {
    const double reach = a * a + b * b;
    if (reach > support)
    {
      const double pull = support > 0.0 ? std::sqrt (support / reach) : 0.0;
      a *= pull;
      b *= pull;
    }
    return quadricHeight (q, a, b);
  }

  /** The signed distance along the normal from p up to the surface, limited to
   *  +-limit when limit > 0. */
  inline double
  move (const Eigen::Vector3d &p, double limit) const
  {
    double a, b;
    coordinates (p, a, b);
    const double m = height (a, b) - (p - origin).dot (normal);
    return limit > 0.0 ? std::clamp (m, -limit, limit) : m;
  }
};

/** The ring points of one fit in its patch's frame, as columns: tangential coordinates
 *  (over the patch radius), height along the normal and weight. Padded with zero-weight
 *  points to a multiple of kLanes, so that QuadricSystem sums them kLanes at a time. */
struct Samples
{
  static constexpr std::size_t kLanes = 4;
  std::vector<double> a, b, h, w;
  std::size_t count = 0;  ///< the points, without the padding

  void
  resize (std::size_t n)
  {
    count = n;
    const std::size_t padded = (n + kLanes - 1) / kLanes * kLanes;
    a.resize (padded);
    b.resize (padded);
    h.resize (padded);
    w.resize (padded);
    std::fill (w.begin (), w.begin () + n, 1.0);
    for (std::size_t r = n; r < padded; ++r)
      a[r] = b[r] = h[r] = w[r] = 0.0;  // the padding
  }

  std::size_t
  padded () const { return a.size (); }
};

/** The weighted least-squares system of a quadric height field, sum_r w_r phi_r phi_r^T q
 *  = sum_r w_r h_r phi_r over the basis, from its 15 distinct moments sum w a^p b^q
 *  (p + q <= 4) and 6 right-hand moments sum w h a^p b^q (p + q <= 2): half the work of
 *  the 6 x 6 outer products. The samples are summed in Samples::kLanes lanes, sample r in
 *  lane r mod kLanes, then the lanes added pairwise: the same sums on every machine, in a
 *  kernel (wide_kernels.h) that the compiler vectorises, four lanes to an instruction in
 *  the AVX2 build. */
class QuadricSystem
{
public:
  explicit QuadricSystem (const Samples &s)
  {
    constexpr std::size_t L = Samples::kLanes;
    const auto sum = [&] (std::size_t begin, std::size_t end) PCL_GRAPH_DENOISE_KERNEL {
      const double *__restrict sa = s.a.data (), *__restrict sb = s.b.data ();
      const double *__restrict sh = s.h.data (), *__restrict sw = s.w.data ();
      double lm[15][L] = {}, lr[6][L] = {};
      for (std::size_t k = begin; k < end; k += L)
        for (std::size_t l = 0; l < L; ++l)
        {
          const double a = sa[k + l], b = sb[k + l], h = sh[k + l], w = sw[k + l];
          const double wa = w * a, wb = w * b;
          const double wa2 = wa * a, wab = wa * b, wb2 = wb * b;
          const double wa3 = wa2 * a, wa2b = wa2 * b, wab2 = wab * b, wb3 = wb2 * b;
          lm[0][l] += w;
          lm[1][l] += wa;
          lm[2][l] += wb;
          lm[3][l] += wa2;
          lm[4][l] += wab;
          lm[5][l] += wb2;
          lm[6][l] += wa3;
          lm[7][l] += wa2b;
          lm[8][l] += wab2;
          lm[9][l] += wb3;
          lm[10][l] += wa3 * a;
          lm[11][l] += wa3 * b;
          lm[12][l] += wa2b * b;
          lm[13][l] += wab2 * b;
          lm[14][l] += wb3 * b;
          lr[0][l] += wa2 * h;
          lr[1][l] += wab * h;
          lr[2][l] += wb2 * h;
          lr[3][l] += wa * h;
          lr[4][l] += wb * h;
          lr[5][l] += w * h;
        }
      for (int i = 0; i < 15; ++i)
        m_[i] = (lm[i][0] + lm[i][1]) + (lm[i][2] + lm[i][3]);
      for (int i = 0; i < 6; ++i)
        r_[i] = (lr[i][0] + lr[i][1]) + (lr[i][2] + lr[i][3]);
    };
    detail::wide (sum, 0, s.padded ());
  }

  /** The normal matrix over the basis (a^2, ab, b^2, a, b, 1). */
  Eigen::Matrix<double, 6, 6>
  matrix () const
  {
    // Moment indices: 1 0, a 1, b 2, a2 3, ab 4, b2 5, a3 6, a2b 7, ab2 8, b3 9, a4 10,
    // a3b 11, a2b2 12, ab3 13, b4 14.
    static constexpr int index[6][6] = {{10, 11, 12, 6, 7, 3}, {11, 12, 13, 7, 8, 4},
                                        {12, 13, 14, 8, 9, 5}, {6, 7, 8, 3, 4, 1},
                                        {7, 8, 9, 4, 5, 2},    {3, 4, 5, 1, 2, 0}};
    Eigen::Matrix<double, 6, 6> m;
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c < 6; ++c)
        m (r, c) = m_[index[r][c]];
    return m;
  }

  Basis
  rhs () const { return Basis (r_); }

private:
  double m_[15];
  double r_[6];
};

/** Whether an LDLT factorisation of a 6 x 6 normal matrix has a reciprocal condition
 *  number above 1e-10 as Eigen estimates it (rcond ()), the test of a usable fit. The
 *  estimate costs several solves and is needed only when the pivots are far apart: the
 *  matrix is positive semi-definite and Eigen pivots on the largest diagonal entry, so the
 *  unit lower factor's entries are at most 1 in size, ||L||_1 <= 6, ||L^-1||_1 <= 2^5, and
 *  the condition number is at most (6 x 32)^2 max|D| / min|D|: with min|D| > 1e-5 max|D|,
 *  below 3.7e9, so the true reciprocal condition number and the estimate (never below
 *  the true one) are above 2.7e-10. */
bool
wellConditioned (const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> &ldlt)
{
  const auto d = ldlt.vectorD ().cwiseAbs ();
  if (d.minCoeff () > 1e-5 * d.maxCoeff ())
    return true;
  return ldlt.rcond () > 1e-10;
}

/** The weighted least-squares quadric of `samples` in q; false (q untouched) when too few
 *  points keep weight for a well-conditioned system, or the solution is not finite. */
bool
solveQuadric (const Samples &samples, Basis &q)
{
  const QuadricSystem system (samples);
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt (system.matrix ());
  if (ldlt.info () != Eigen::Success || !wellConditioned (ldlt))
    return false;
  const Basis solved = ldlt.solve (system.rhs ());
  if (!solved.allFinite ())
    return false;
  q = solved;
  return true;
}

/** Fits vertex i's patch to the points of x over `ring` (its two rings, or three),
 *  robustly with a noise level > 0 (quadricDisplacement). `moments`: vertex i's, holding
 *  the sums of the ring's first points when an earlier fit used them. `samples` receives
 *  the ring's points in the patch's frame, in the ring's order (count 0 when the patch
 *  has no extent or too few points for a quadric). `fitted`, when given: whether a quadric was
 *  fitted (else the patch is the plane, or invalid). */
Patch
fitPatch (const Signal3 &x, const std::vector<VertexIndex> &ring, std::size_t i, double noise,
          detail::RingMoments &moments, Samples &samples, bool *fitted = nullptr)
{
  if (fitted)
    *fitted = false;
  samples.count = 0;  // until they are filled, below
  Patch patch;
  if (ring.size () < 3)
    return patch;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect (moments.covariance (x, ring));
  patch.support = 0.0;
  patch.origin = x.row (i).transpose ();
  patch.normal = eig.eigenvectors ().col (0);
  const double radius = std::sqrt (eig.eigenvalues ()(2) + eig.eigenvalues ()(1));
  if (!(radius > 0.0))
    return patch;  // the plane through x_i, without extent
  patch.u = eig.eigenvectors ().col (2) / radius;  // normal x u: the middle axis / radius
  if (ring.size () < kQuadricMinimumRing)
    return patch;  // the plane through x_i
  samples.resize (ring.size ());
  for (std::size_t r = 0; r < ring.size (); ++r)
  {
    const Eigen::Vector3d p = x.row (ring[r]).transpose ();
    patch.coordinates (p, samples.a[r], samples.b[r]);
    samples.h[r] = (p - patch.origin).dot (patch.normal);
    patch.support = std::max (patch.support, samples.a[r] * samples.a[r] + samples.b[r] * samples.b[r]);
  }  const bool robust = noise > 0.0;
  // Robust: the first weights come from the plane through x_i (q = 0), so that a point
  // between two sheets starts on its own side.
  for (int iteration = 0; iteration < (robust ? kRobustIterations : 1); ++iteration)
  {
    if (robust)
    {
      // Over the whole ring in a kernel, with the vectorised exp (one std::exp per
      // sample was the largest single cost of the fits).
      const Basis q = patch.q;
      const auto weigh = [&] (std::size_t begin, std::size_t end) PCL_GRAPH_DENOISE_KERNEL {
        const double *__restrict sa = samples.a.data (), *__restrict sb = samples.b.data ();
        const double *__restrict sh = samples.h.data ();
        double *__restrict sw = samples.w.data ();
        for (std::size_t r = begin; r < end; ++r)
        {
          const double t = (sh[r] - quadricHeight (q, sa[r], sb[r])) / noise;
          sw[r] = detail::expOfNonPositive (-0.5 * t * t);
        }
      };
      detail::wide (weigh, 0, samples.count);
    }
    Basis solved;
    if (!solveQuadric (samples, solved))
      break;  // too few points keep weight: keep the last fit (or the plane)
    // From the second fit on: settled once it moved the surface by at most kRobustStop
    // noise levels at every point.
    bool settled = robust && iteration > 0;
    if (settled)
    {
      const Basis change = solved - patch.q;
      for (std::size_t r = 0; r < samples.count && settled; ++r)
        settled = std::abs (quadricHeight (change, samples.a[r], samples.b[r])) <= kRobustStop * noise;
    }
    patch.q = solved;
    if (fitted)
      *fitted = true;
    if (settled)
      break;
  }
  return patch;
}

/** Whether a wider fit clearly agrees with the narrower ring's points: the least-squares
 *  quadric of `moves` (the wider surface's height minus each point's, for the first
 *  `moves.size ()` samples, the narrower ring's) changes their heights by a sum of
 *  squares of at most `bound`. `scratch` holds those residuals as samples. */
bool
residualsWithin (const Samples &samples, const std::vector<double> &moves, double bound,
                 Samples &scratch)
{
  scratch.resize (moves.size ());
  for (std::size_t r = 0; r < moves.size (); ++r)
  {
    scratch.a[r] = samples.a[r];
    scratch.b[r] = samples.b[r];
    scratch.h[r] = -moves[r];
  }
  Basis c;
  if (!solveQuadric (scratch, c))
    return false;
  double sum = 0.0;
  for (std::size_t r = 0; r < moves.size (); ++r)
  {
    const double d = quadricHeight (c, samples.a[r], samples.b[r]);
    sum += d * d;
  }
  return sum <= bound;
}

} // namespace

std::vector<std::uint8_t>
patchCentres (const PointGraph &graph, int cover)
{
  if (cover < 0)
    throw std::invalid_argument ("patchCentres: the cover must be >= 0");
  const std::size_t n = graph.numVertices ();
  std::vector<std::uint8_t> centre (n, 1);
  if (cover == 0)
    return centre;
  // How many neighbours of each vertex carry a patch so far.
  std::vector<std::uint32_t> covered (n, 0);
  for (std::size_t v = 0; v < n; ++v)
  {
    centre[v] = covered[v] < std::uint32_t (cover);
    if (centre[v])
      for (std::uint64_t e = graph.row_ptr[v]; e < graph.row_ptr[v + 1]; ++e)
        ++covered[graph.col[e]];
  }
  return centre;
}

Signal3
quadricDisplacement (const PointGraph &graph, const Signal3 &f, const Signal3 &x, double noise,
                     int num_threads, QuadricProjection projection, QuadricSupport support,
                     int patch_cover)
{
  const std::size_t n = graph.numVertices ();
  if (static_cast<std::size_t> (f.rows ()) != n || static_cast<std::size_t> (x.rows ()) != n)
    throw std::invalid_argument ("quadricDisplacement: signals of the wrong size");
  if (patch_cover < 0)
    throw std::invalid_argument ("quadricDisplacement: the patch cover must be >= 0");
  if (!std::isfinite (noise) || !(noise > 0.0))
    noise = 0.0;  // not robust
  const bool blend = projection == QuadricProjection::BLENDED;
  const bool adaptive = support == QuadricSupport::ADAPTIVE && noise > 0.0;
  // With a noise level, a point moves along a normal by at most the smoothing's own
  // move plus three noise levels: a fit that still goes astray cannot throw it away.
  const auto limit = [&] (std::size_t i) {
    return noise > 0.0 ? (f.row (i) - x.row (i)).norm () + 3.0 * noise : 0.0;
  };
  Signal3 out = detail::matrixOnHugePages<Signal3> (x.rows ());
  out = x;
  // Without a blend every point needs its own patch.
  const std::vector<std::uint8_t> centre = patchCentres (graph, blend ? patch_cover : 0);
  // The blend keeps the patch of each vertex that carries one, patches[slot[v]] (at a
  // million points and a cover of 3, 40% of them: 52 MB rather than 136).
  constexpr VertexIndex kNoPatch = std::numeric_limits<VertexIndex>::max ();
  std::vector<VertexIndex> slot;
  std::vector<Patch> patches;
  if (blend)
  {
    slot.resize (n);
    VertexIndex count = 0;
    for (std::size_t v = 0; v < n; ++v)
      slot[v] = centre[v] ? count++ : kNoPatch;
    detail::resizeOnHugePages (patches, count);
  }
  detail::parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    std::vector<VertexIndex> ring;
    Samples samples, residual_samples;
    std::vector<double> wide_move;
    detail::TwoRing two_ring;
    for (std::size_t i = begin; i < end; ++i)
    {
      if (!centre[i])
        continue;  // borrows its neighbours' patches
      two_ring.collect (graph, i, ring);
      if (support == QuadricSupport::THREE_RINGS)
        two_ring.grow (graph, ring);
      bool fitted = false;
      detail::RingMoments moments (i);
      Patch patch;
      bool done = false;
      const std::size_t narrow_size = ring.size ();
      const double agreement = 6.0 * kSupportAgreement * kSupportAgreement * noise * noise;
      Patch wide;
      bool wide_usable = false;
      // Adaptive support: the wider (three-ring) fit where its surface, under the narrower
      // ring's points, stays within the noise of the narrower (two-ring) one's. The wider
      // fit comes first; where the least-squares quadric of its residuals under the
      // narrower ring's points clearly stays within that bound, it is taken without the
      // narrower fit; else the narrower is fitted and the two compared, each surface's
      // move of those points along its normal from its own fit's samples. (No wider fit
      // where the next ring is too large to collect: a dense graph.)
      if (adaptive && narrow_size >= kQuadricMinimumRing && two_ring.grow (graph, ring))
      {
        bool wide_fitted = false;
        wide = fitPatch (x, ring, i, noise, moments, samples, &wide_fitted);
        wide_usable = wide.valid () && samples.count == ring.size ();
        if (wide_usable)
        {
          wide_move.resize (narrow_size);
          for (std::size_t r = 0; r < narrow_size; ++r)
            wide_move[r] = quadricHeight (wide.q, samples.a[r], samples.b[r]) - samples.h[r];
          done = wide_fitted &&
                 residualsWithin (samples, wide_move, kClearAgreement * agreement, residual_samples);
          if (done)
            patch = wide;
        }
        if (!done)
          ring.resize (narrow_size);
      }
      if (!done)
      {
        patch = fitPatch (x, ring, i, noise, moments, samples, &fitted);
        if (fitted && wide_usable)
        {
          double sum = 0.0;
          for (std::size_t r = 0; r < narrow_size; ++r)
          {
            const double narrow_move = quadricHeight (patch.q, samples.a[r], samples.b[r]) - samples.h[r];
            sum += (narrow_move * patch.normal - wide_move[r] * wide.normal).squaredNorm ();
          }
          if (sum <= agreement)
            patch = wide;
        }
      }
      if (blend)
        patches[slot[i]] = patch;
      else if (patch.valid ())  // else keeps x_i
      {
        const Eigen::Vector3d fi = f.row (i).transpose ();
        out.row (i) = (fi + patch.move (fi, limit (i)) * patch.normal).transpose ();
      }
    }
  });
  if (!blend)
    return out;
  // Each point onto the weighted mean of its own and its two rings' surfaces: a patch
  // counts by how close the smoothed point x_i lies to its centre (tangentially) and,
  // robustly, to its surface, so that a patch of another sheet drops out.
  detail::parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    std::vector<VertexIndex> ring;
    detail::TwoRing two_ring;
    // Each patch's exponent (then its weight) and the point it moves f_i to; the weights
    // are taken over the ring at once in a kernel (wide_kernels.h).
    std::vector<double> weight;
    std::vector<Eigen::Vector3d> moved;
    const Patch none;  // of a vertex that carries none
    for (std::size_t i = begin; i < end; ++i)
    {
      const Patch &own = centre[i] ? patches[slot[i]] : none;
      if (centre[i] && !own.valid ())
        continue;  // keeps x_i
      two_ring.collect (graph, i, ring);
      const Eigen::Vector3d fi = f.row (i).transpose ();
      const Eigen::Vector3d xi = x.row (i).transpose ();
      const double reach = limit (i);
      weight.clear ();
      moved.clear ();
      for (VertexIndex j : ring)
      {
        if (slot[j] == kNoPatch)
          continue;
        const Patch &patch = patches[slot[j]];
        if (!patch.valid ())
          continue;
        double a, b;
        patch.coordinates (xi, a, b);
        double exponent = (a * a + b * b) / (2.0 * kBlendReach * kBlendReach);
        if (noise > 0.0)
        {
          const double t = (patch.height (a, b) - (xi - patch.origin).dot (patch.normal)) / noise;
          exponent += 0.5 * t * t;
        }
        weight.push_back (-exponent);
        moved.push_back (fi + patch.move (fi, reach) * patch.normal);
      }
      const auto weigh = [&] (std::size_t b, std::size_t e) PCL_GRAPH_DENOISE_KERNEL {
        double *__restrict w = weight.data ();
        for (std::size_t k = b; k < e; ++k)
          w[k] = detail::expOfNonPositive (w[k]);
      };
      detail::wide (weigh, 0, weight.size ());
      Eigen::Vector3d sum = Eigen::Vector3d::Zero ();
      double total = 0.0;
      for (std::size_t k = 0; k < weight.size (); ++k)
      {
        sum += weight[k] * moved[k];
        total += weight[k];
      }
      // When every patch ignores it, its own surface (a point without one keeps x_i).
      if (!(total > 0.0) && !own.valid ())
        continue;
      const Eigen::Vector3d merged = total > 0.0 ? Eigen::Vector3d (sum / total)
                                                 : Eigen::Vector3d (fi + own.move (fi, reach) * own.normal);
      out.row (i) = merged.transpose ();
    }
  });
  return out;
}

namespace {

/** The offset of one point's local surface between two clouds (surfaceOffsets). */
struct LocalOffset
{
  Eigen::Vector3d normal = Eigen::Vector3d::Zero ();
  double offset = 0.0;          ///< along the normal
  double standard_error = 0.0;  ///< of `offset`
  bool matched = false;         ///< the reference samples the same part of the surface
};

/** The direction of least variance of the pooled scatter of two point sets, each about
 *  its own mean (two locally parallel surfaces); the means in `means`. */
Eigen::Vector3d
pooledNormal (const std::vector<Eigen::Vector3d> &a, const std::vector<Eigen::Vector3d> &b,
              Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> &eig, Eigen::Vector3d (&means)[2])
{
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero ();
  const std::vector<Eigen::Vector3d> *sets[2] = {&a, &b};
  for (int s = 0; s < 2; ++s)
  {
    Eigen::Vector3d &mean = means[s];
    mean.setZero ();
    for (const Eigen::Vector3d &p : *sets[s])
      mean += p;
    mean /= double (std::max<std::size_t> (sets[s]->size (), 1));
    for (const Eigen::Vector3d &p : *sets[s])
      scatter += (p - mean) * (p - mean).transpose ();
  }
  eig.compute (scatter);
  return eig.eigenvectors ().col (0);
}

/** surfaceOffsets' estimate for every `stride`-th row of `current` (the moving points in
 *  Morton order, possibly moved rigidly; `own` lists each row's 2k nearest points in its
 *  own cloud, nearest first, `counts` per row, 2k slots per row), against the reference
 *  cloud's tree; the other rows are left unmatched. */
std::vector<LocalOffset>
localOffsets (const PointMatrix &current, const std::vector<VertexIndex> &own,
              const std::vector<std::size_t> &counts, const PointMatrix &reference,
              const detail::KdTree &other, int k, std::size_t stride, int num_threads)
{
  const std::size_t n = static_cast<std::size_t> (current.rows ());
  std::vector<LocalOffset> out (n);
  // Up to this many points of either cloud per point: a reference up to twice as dense
  // samples the moving point's whole neighbourhood; a denser one, a smaller disk.
  const int reference_cap = 2 * k;
  detail::parallelFor ((n + stride - 1) / stride, num_threads, [&] (std::size_t begin, std::size_t end) {
    std::vector<VertexIndex> idx_b (static_cast<std::size_t> (reference_cap));
    std::vector<float> d2 (static_cast<std::size_t> (reference_cap));
    std::vector<Eigen::Vector3d> a, b;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    for (std::size_t i = begin * stride; i < std::min (n, end * stride); i += stride)
    {
      const Eigen::Vector3d q = current.row (static_cast<Eigen::Index> (i)).transpose ().cast<double> ();
      const VertexIndex *idx_a = own.data () + i * std::size_t (reference_cap);
      const std::size_t found =
          other.nearest (current.row (static_cast<Eigen::Index> (i)).data (), reference_cap,
                         idx_b.data (), d2.data ());
      // Both surfaces sampled over the same disk around q: the mean of a curved patch
      // lies below it by an amount that grows with the patch's extent, so neighbourhoods
      // of different extents (frames of different densities) would read the curvature
      // as an offset. The disk is measured across the normal of the two neighbourhoods
      // as found, the moving point's k nearest and the reference's `reference_cap`
      // nearest (the surfaces may lie apart by more than its radius): as far as the
      // moving point's k nearest reach, or the reference's where those reach less far.
      // Both clouds' points are taken from their `reference_cap` nearest alike, so that
      // at a sharp edge, where the disk's cylinder takes in points of the other face
      // beyond the k nearest, it does so for both.
      const auto point = [] (const PointMatrix &p, VertexIndex r) {
        return Eigen::Vector3d (p.row (r).transpose ().cast<double> ());
      };
      const std::size_t own_k = std::min<std::size_t> (counts[i], std::size_t (k));
      a.clear ();
      b.clear ();
      for (std::size_t m = 0; m < own_k; ++m)
        a.push_back (point (current, idx_a[m]));
      for (std::size_t m = 0; m < found; ++m)
        b.push_back (point (reference, idx_b[m]));
      Eigen::Vector3d means[2];
      const Eigen::Vector3d axis = pooledNormal (a, b, eig, means);
      const auto across = [&] (const Eigen::Vector3d &p) {
        const Eigen::Vector3d d = p - q;
        return (d - d.dot (axis) * axis).squaredNorm ();
      };
      double radius2 = 0.0;
      for (const Eigen::Vector3d &p : a)
        radius2 = std::max (radius2, across (p));
      for (std::size_t m = own_k; m < counts[i]; ++m)
        a.push_back (point (current, idx_a[m]));
      if (found == static_cast<std::size_t> (reference_cap))
      {
        double reach2 = 0.0;
        for (const Eigen::Vector3d &p : b)
          reach2 = std::max (reach2, across (p));
        radius2 = std::min (radius2, reach2);
      }
      // And within one ball that both pools cover, around q for the moving points and
      // around q moved by the neighbourhoods' offset for the reference.
      const Eigen::Vector3d q_b = q + axis * axis.dot (means[1] - means[0]);
      double ball2 = std::numeric_limits<double>::infinity ();
      if (counts[i] == std::size_t (reference_cap))
      {
        double r2 = 0.0;
        for (const Eigen::Vector3d &p : a)
          r2 = std::max (r2, (p - q).squaredNorm ());
        ball2 = std::min (ball2, r2);
      }
      if (found == std::size_t (reference_cap))
      {
        double r2 = 0.0;
        for (const Eigen::Vector3d &p : b)
          r2 = std::max (r2, (p - q_b).squaredNorm ());
        ball2 = std::min (ball2, r2);
      }
      a.erase (std::remove_if (a.begin (), a.end (), [&] (const Eigen::Vector3d &p) {
        return across (p) > radius2 || (p - q).squaredNorm () > ball2;
      }), a.end ());
      b.erase (std::remove_if (b.begin (), b.end (), [&] (const Eigen::Vector3d &p) {
        return across (p) > radius2 || (p - q_b).squaredNorm () > ball2;
      }), b.end ());
      LocalOffset &o = out[i];
      const std::size_t na = a.size (), nb = b.size ();
      if (na < 3 || nb < 3)
        continue;  // too few points of one cloud in the disk: unmatched
      o.normal = pooledNormal (a, b, eig, means);
      const Eigen::Vector3d &ca = means[0], &cb = means[1];
      double sa = 0.0, sb = 0.0;
      for (const Eigen::Vector3d &p : a)
        sa += std::pow (o.normal.dot (p - ca), 2);
      for (const Eigen::Vector3d &p : b)
        sb += std::pow (o.normal.dot (p - cb), 2);
      o.standard_error =
          std::sqrt (sa / (double (na) * double (na - 1)) + sb / (double (nb) * double (nb - 1)));
      o.offset = o.normal.dot (cb - ca);
      // Without a counterpart (the reference does not cover this part of the surface, its
      // nearest points are off to the side), no offset.
      double reach = 0.0;
      for (const Eigen::Vector3d &p : a)
        reach = std::max (reach, (p - ca).norm ());
      o.matched = (cb - ca - o.offset * o.normal).norm () <= reach;
      if (!o.matched)
        o.offset = 0.0;
    }
  });
  return out;
}

/** The rigid motion (small rotation omega about `centre`, translation tau) that best
 *  explains the offsets along the normals, n . (omega x (q - c) + tau) = offset, in least
 *  squares over the points whose residual is within 3 robust deviations of the first
 *  fit's. Directions the normals do not constrain (turning a sphere about its centre,
 *  sliding a plane along itself) get no motion, and each principal direction of the fit
 *  is shrunk as the offsets are (non-negative garrote at `significance` of its standard
 *  error, the larger of the residuals' robust spread and the offsets' own standard errors
 *  carried through the fit; directions constrained a hundred times less than the best
 *  get none): few or noisy offsets, or normals that barely constrain a direction, make
 *  no motion out of their noise. Only the matched
 *  points take part. Returns false when fewer than 6 are matched or the step is
 *  negligible. */
bool
rigidStep (const PointMatrix &current, const std::vector<LocalOffset> &offsets,
           double significance, Eigen::Matrix3d &rotation, Eigen::Vector3d &translation)
{
  const std::size_t n = offsets.size ();
  const Eigen::Vector3d centre = current.colwise ().mean ().transpose ().cast<double> ();
  double radius = 0.0;
  for (std::size_t i = 0; i < n; ++i)
    radius += (current.row (i).transpose ().cast<double> () - centre).squaredNorm ();
  radius = std::sqrt (radius / double (n));
  if (!(radius > 0.0))
    return false;
  if (std::count_if (offsets.begin (), offsets.end (),
                     [] (const LocalOffset &o) { return o.matched; }) < 6)
    return false;
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  const auto row = [&] (std::size_t i) {
    Vector6d a;
    const Eigen::Vector3d q = (current.row (i).transpose ().cast<double> () - centre) / radius;
    a << q.cross (offsets[i].normal), offsets[i].normal;
    return a;
  };
  std::vector<double> residual (n, 0.0);
  Vector6d x = Vector6d::Zero ();
  double cut = std::numeric_limits<double>::infinity ();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig;
  Vector6d g;
  // The offsets' own errors carried through the fit: sum of a a^T se^2.
  Eigen::Matrix<double, 6, 6> offset_errors;
  for (int pass = 0; pass < 2; ++pass)
  {
    Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero ();
    g.setZero ();
    offset_errors.setZero ();
    for (std::size_t i = 0; i < n; ++i)
      if (offsets[i].matched && std::abs (residual[i]) <= cut)
      {
        const Vector6d a = row (i);
        h += a * a.transpose ();
        g += a * offsets[i].offset;
        offset_errors += a * a.transpose () * (offsets[i].standard_error * offsets[i].standard_error);
      }
    eig.compute (h);
    const double largest = eig.eigenvalues ().maxCoeff ();
    if (!(largest > 0.0))
      return false;
    x.setZero ();
    for (int e = 0; e < 6; ++e)
      if (eig.eigenvalues ()[e] > 1e-3 * largest)
        x += eig.eigenvectors ().col (e) * (eig.eigenvectors ().col (e).dot (g) / eig.eigenvalues ()[e]);
    std::vector<double> abs_residual;
    for (std::size_t i = 0; i < n; ++i)
    {
      residual[i] = offsets[i].offset - row (i).dot (x);
      if (offsets[i].matched)
        abs_residual.push_back (std::abs (residual[i]));
    }
    const std::size_t half = abs_residual.size () / 2;
    std::nth_element (abs_residual.begin (), abs_residual.begin () + half, abs_residual.end ());
    cut = 3.0 * abs_residual[half] / 0.6744897501960817;
  }
  // Each principal component c of the last fit, shrunk: 0 below `significance`
  // standard errors, c - limit^2 / c above. Its standard error: the larger of the one
  // the residuals' spread gives, spread / sqrt (eigenvalue), and the one the offsets'
  // own standard errors give (a few offsets fit by six parameters leave small
  // residuals). Directions constrained a hundred times less than the best one (the
  // normals' noise alone) get no motion.
  const double spread = cut / 3.0;
  const double largest = eig.eigenvalues ().maxCoeff ();
  x.setZero ();
  for (int e = 0; e < 6; ++e)
  {
    const double lambda = eig.eigenvalues ()[e];
    if (!(lambda > 1e-2 * largest))
      continue;
    const Vector6d v = eig.eigenvectors ().col (e);
    const double c = v.dot (g) / lambda;
    const double error = std::max (spread / std::sqrt (lambda), std::sqrt (v.dot (offset_errors * v)) / lambda);
    const double limit = significance * error;
    if (std::abs (c) > limit)
      x += eig.eigenvectors ().col (e) * (c - limit * limit / c);
  }
  // Done when the step moves no point by more than a hundredth of the offsets' typical
  // standard error (x is in length units: the rotation part is scaled by the radius, and
  // the points lie within about 2 radii of the centre).
  std::vector<double> errors;
  for (const LocalOffset &o : offsets)
    if (o.matched)
      errors.push_back (o.standard_error);
  std::nth_element (errors.begin (), errors.begin () + errors.size () / 2, errors.end ());
  if (2.0 * x.norm () < 0.01 * errors[errors.size () / 2])
    return false;
  const Eigen::Vector3d omega = x.head<3> () / radius;
  const double angle = omega.norm ();
  rotation = angle > 0.0 ? Eigen::AngleAxisd (angle, omega / angle).toRotationMatrix ()
                         : Eigen::Matrix3d::Identity ();
  translation = centre + x.tail<3> () - rotation * centre;
  return true;
}

/** surfaceOffsets on points in Morton order (both clouds: the searches then walk the
 *  trees in order). */
Signal3
orderedSurfaceOffsets (const PointMatrix &moving, const PointMatrix &reference,
                       const SurfaceOffsetParams &params)
{
  const std::size_t n = static_cast<std::size_t> (moving.rows ());
  Signal3 offsets = Signal3::Zero (moving.rows (), 3);
  const int k = params.k;

  // Each moving point's 2k nearest points in its own cloud, nearest first (they stay its
  // neighbours under a rigid motion): localOffsets compares disks of them, the offsets
  // are averaged over the k nearest.
  const std::size_t slots = 2 * std::size_t (k);
  std::vector<VertexIndex> own (n * slots);
  std::vector<std::size_t> counts (n);
  {
    const detail::KdTree tree (moving);
    detail::parallelFor (n, params.num_threads, [&] (std::size_t begin, std::size_t end) {
      std::vector<float> d2 (slots);
      for (std::size_t i = begin; i < end; ++i)
        counts[i] = tree.nearest (moving.row (static_cast<Eigen::Index> (i)).data (), int (slots),
                                  own.data () + i * slots, d2.data ());
    });
  }
  const detail::KdTree other (reference);

  // The rigid part of the motion first, then what it leaves along the normals.
  PointMatrix current = moving;
  Eigen::Matrix3d total_rotation = Eigen::Matrix3d::Identity ();
  Eigen::Vector3d total_translation = Eigen::Vector3d::Zero ();
  // The rigid fit on a spatially even subsample of about 20,000 points (every stride-th
  // in Morton order) is as good and much cheaper.
  const std::size_t stride = std::max<std::size_t> (1, n / 20000);
  std::vector<LocalOffset> local =
      localOffsets (current, own, counts, reference, other, k, stride, params.num_threads);
  for (int it = 0; it < params.rigid_iterations; ++it)
  {
    Eigen::Matrix3d rotation;
    Eigen::Vector3d translation;
    if (!rigidStep (current, local, params.significance, rotation, translation))
      break;
    total_rotation = rotation * total_rotation;
    total_translation = rotation * total_translation + translation;
    for (std::size_t i = 0; i < n; ++i)
      current.row (i) = (total_rotation * moving.row (i).transpose ().cast<double> () +
                         total_translation).transpose ().cast<float> ();
    local = localOffsets (current, own, counts, reference, other, k, stride, params.num_threads);
  }
  if (stride > 1)
    local = localOffsets (current, own, counts, reference, other, k, 1, params.num_threads);

  // Each point's offset, shrunk where it is not significant (non-negative garrote: zero
  // below `significance` standard errors, little shrinkage far above), then averaged
  // over the point's neighbours (the motion of a surface is smooth; the estimates' noise
  // is not).
  Signal3 shrunk (moving.rows (), 3);
  for (std::size_t i = 0; i < n; ++i)
  {
    const double offset = local[i].offset;
    const double limit = params.significance * local[i].standard_error;
    const double value = std::abs (offset) > limit ? offset - limit * limit / offset : 0.0;
    shrunk.row (static_cast<Eigen::Index> (i)) = value * local[i].normal.transpose ();
  }
  detail::parallelFor (n, params.num_threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const std::size_t count = std::min (counts[i], std::size_t (k));
      Eigen::RowVector3d sum = Eigen::RowVector3d::Zero ();
      for (std::size_t m = 0; m < count; ++m)
        sum += shrunk.row (own[i * slots + m]);
      offsets.row (static_cast<Eigen::Index> (i)) =
          current.row (static_cast<Eigen::Index> (i)).cast<double> () -
          moving.row (static_cast<Eigen::Index> (i)).cast<double> () + sum / double (count);
    }
  });
  return offsets;
}

} // namespace

Signal3
surfaceOffsets (const PointMatrix &moving, const PointMatrix &reference,
                const SurfaceOffsetParams &params)
{
  if (params.k < 3)
    throw std::invalid_argument ("surfaceOffsets: k must be >= 3");
  if (!(std::isfinite (params.significance) && params.significance >= 0.0))
    throw std::invalid_argument ("surfaceOffsets: significance must be finite and >= 0");
  if (params.rigid_iterations < 0)
    throw std::invalid_argument ("surfaceOffsets: rigid_iterations must be >= 0");
  if (params.num_threads < 0)
    throw std::invalid_argument ("surfaceOffsets: num_threads must be >= 0");
  if (!moving.allFinite () || !reference.allFinite ())
    throw std::invalid_argument ("surfaceOffsets: points must be finite");
  Signal3 offsets = Signal3::Zero (moving.rows (), 3);
  if (moving.rows () < 3 || reference.rows () < 3)
    return offsets;
  const std::vector<VertexIndex> order = detail::mortonOrder (moving, params.num_threads);
  const Signal3 ordered = orderedSurfaceOffsets (
      detail::reorderPoints (moving, order),
      detail::reorderPoints (reference, detail::mortonOrder (reference, params.num_threads)),
      params);
  for (std::size_t v = 0; v < order.size (); ++v)
    offsets.row (order[v]) = ordered.row (static_cast<Eigen::Index> (v));
  return offsets;
}

} // namespace core
} // namespace pcl_graph_denoise
