/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "neighbor_search.h"

// Among equidistant candidates keep the lowest index: ties resolve the same way
// as a brute-force search sorted by (distance, index).
#define NANOFLANN_FIRST_MATCH
#include <nanoflann.hpp>

#include "parallel.h"
#include "rank_sort.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <limits>
#include <memory>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

namespace {

/** nanoflann dataset adaptor over a row-major N x 3 float matrix. */
struct MatrixDataset
{
  const PointMatrix &points;

  std::size_t
  kdtree_get_point_count () const { return static_cast<std::size_t> (points.rows ()); }

  float
  kdtree_get_pt (std::size_t i, std::size_t d) const { return points (i, d); }

  template <typename BoundingBox>
  bool
  kdtree_get_bbox (BoundingBox &) const { return false; }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<float, MatrixDataset, float, VertexIndex>, MatrixDataset, 3,
    VertexIndex>;

/** Relative slack of every comparison of a single-precision squared distance with a
 *  bound computed otherwise (a cell's distance in double precision, or nanoflann's
 *  running bound in single precision, which can come out a few ulps high): far larger
 *  than their relative rounding. */
constexpr double kSlack = 1e-5;

/** Absolute slack of the same comparisons: a squared distance below the smallest normal
 *  float may have underflowed to a subnormal or to 0. */
constexpr double kTinySquared = 4.0 * double (FLT_MIN);

/** Whether a point at squared distance `bound2` or more (in exact arithmetic) may have
 *  a single-precision squared distance at or below `worst`. */
inline bool
mayReach (double bound2, float worst)
{
  return bound2 <= double (worst) * (1.0 + kSlack) + kTinySquared;
}

/** The k nearest candidates offered so far, by (squared distance, index), ascending:
 *  each packed in 64 bits, the distance's bits above the index (a non-negative float's
 *  bits order as the float does), so that comparing two is one integer comparison.
 *  Works on k keys the caller holds. */
class NearestK
{
public:
  explicit NearestK (std::vector<std::uint64_t> &keys) : key_ (keys) {}

  void
  clear () { std::fill (key_.begin (), key_.end (), kNone); }

  /** The k-th squared distance so far, infinite while fewer than k were offered. */
  float
  worst () const
  {
    return full () ? distance (key_.back ()) : std::numeric_limits<float>::infinity ();
  }

  bool
  full () const { return key_.back () != kNone; }

  static std::uint64_t
  key (float d2, VertexIndex id)
  {
    std::uint32_t bits;
    std::memcpy (&bits, &d2, sizeof bits);
    return (std::uint64_t (bits) << 32) | id;
  }

  /** The k smallest of the m >= k distinct keys at `keys` (which it reorders). */
  void
  take (std::uint64_t *keys, std::size_t m)
  {
    smallestFirst (keys, m, key_.size ());
    std::copy (keys, keys + key_.size (), key_.begin ());
  }

  void
  offer (float d2, VertexIndex id)
  {
    const std::uint64_t key = NearestK::key (d2, id);
    if (key >= key_.back ())
      return;
    std::size_t p = key_.size () - 1;
    for (; p > 0 && key_[p - 1] > key; --p)
      key_[p] = key_[p - 1];
    key_[p] = key;
  }

  /** Writes the indices; returns the mean distance. Needs full(). */
  double
  write (VertexIndex *indices) const
  {
    double sum = 0.0;
    for (std::size_t m = 0; m < key_.size (); ++m)
    {
      indices[m] = static_cast<VertexIndex> (key_[m]);
      sum += std::sqrt (double (distance (key_[m])));
    }
    return sum / double (key_.size ());
  }

private:
  static constexpr std::uint64_t kNone = ~std::uint64_t (0);

  static float
  distance (std::uint64_t key)
  {
    const auto bits = static_cast<std::uint32_t> (key >> 32);
    float d2;
    std::memcpy (&d2, &bits, sizeof d2);
    return d2;
  }

  std::vector<std::uint64_t> &key_;
};

/** A nanoflann result set that ranks by (squared distance, index) itself and admits
 *  everything within the slack of its k-th: nanoflann's own k-NN keeps any one of the
 *  points tied at the k-th distance, and its pruning bound can drop a point a few ulps
 *  nearer. */
class ExactNearest
{
public:
  ExactNearest (NearestK &best, VertexIndex self) : best_ (best), self_ (self) {}

  bool
  full () const { return best_.full (); }

  bool
  addPoint (float d2, VertexIndex id)
  {
    if (id != self_)
      best_.offer (d2, id);
    return true;
  }

  float
  worstDist () const
  {
    return best_.full () ? float (double (best_.worst ()) * (1.0 + kSlack) + kTinySquared)
                         : std::numeric_limits<float>::max ();
  }

private:
  NearestK &best_;
  VertexIndex self_;
};

} // namespace

struct KdTree::Impl
{
  explicit Impl (const PointMatrix &p)
  : data{p}, tree (3, data, nanoflann::KDTreeSingleIndexAdaptorParams (16))
  {}
  MatrixDataset data;
  Tree tree;
};

KdTree::KdTree (const PointMatrix &points) : impl_ (new Impl (points)) {}

KdTree::~KdTree () = default;

void
KdTree::nearestOthers (VertexIndex self, int k, VertexIndex *indices, float *squared_distances,
                       std::vector<VertexIndex> &scratch_idx,
                       std::vector<float> &scratch_d2) const
{
  const std::size_t wanted = static_cast<std::size_t> (k) + 1;
  scratch_idx.resize (wanted);
  scratch_d2.resize (wanted);
  const float *query = impl_->data.points.row (self).data ();
  const std::size_t found =
      impl_->tree.knnSearch (query, wanted, scratch_idx.data (), scratch_d2.data ());
  // Drop the query itself; among duplicates it may be missing, then drop the farthest.
  std::size_t out = 0;
  bool skipped = false;
  for (std::size_t m = 0; m < found && out < static_cast<std::size_t> (k); ++m)
  {
    if (!skipped && scratch_idx[m] == self)
    {
      skipped = true;
      continue;
    }
    indices[out] = scratch_idx[m];
    squared_distances[out] = scratch_d2[m];
    ++out;
  }
}

std::size_t
KdTree::nearest (const float *query, int k, VertexIndex *indices, float *squared_distances) const
{
  const std::size_t wanted =
      std::min (static_cast<std::size_t> (k), impl_->data.kdtree_get_point_count ());
  if (wanted == 0)
    return 0;
  return impl_->tree.knnSearch (query, wanted, indices, squared_distances);
}

void
KdTree::othersWithin (VertexIndex self, float radius, std::vector<VertexIndex> &neighbors,
                      std::vector<std::pair<VertexIndex, float>> &scratch) const
{
  scratch.clear ();
  const float *query = impl_->data.points.row (self).data ();
  // nanoflann's L2 radius is squared and strict: points closer than `radius`.
  impl_->tree.radiusSearch (query, radius * radius, scratch,
                            nanoflann::SearchParams (32, 0.0f, false));
  for (const auto &hit : scratch)
    if (hit.first != self)
      neighbors.push_back (hit.first);
}

double
KdTree::nearestOthersExact (VertexIndex self, int k, VertexIndex *indices,
                            std::vector<std::uint64_t> &scratch) const
{
  scratch.resize (static_cast<std::size_t> (k));
  NearestK best (scratch);
  best.clear ();
  ExactNearest result (best, self);
  impl_->tree.findNeighbors (result, impl_->data.points.row (self).data (),
                             nanoflann::SearchParams (32, 0.0f, false));
  return best.write (indices);
}

namespace {

/** The guess of a point's k-th squared distance: the previous point's of its cell times
 *  this. */
constexpr float kGuessWidening = 1.5f;

/** The grid's cells: the finest at which half the points lie in cells of at least
 *  max(kMinOccupancy, kOccupancyPerNeighbour k) points. Twice k rather than k: the k-NN
 *  graph of noisy spheres and cubes of 1,000,000 points (k = 10) took 15-30% less time,
 *  of points uniform in a cube 10% less (the cells hold more points to share the
 *  gathering of their neighbours' points, and fewer points are left to a coarser grid);
 *  three or four times k gained little more on the surfaces and lost in the volume. */
constexpr std::size_t kMinOccupancy = 4;
constexpr std::size_t kOccupancyPerNeighbour = 2;
/** Cells of more than this many times that occupancy are searched in the k-d tree. */
constexpr std::size_t kCrowdedCell = 16;

/** Open-addressing map from the codes of the grid's cells to their index. */
class CellTable
{
public:
  explicit CellTable (const std::vector<std::uint64_t> &keys)
  {
    std::size_t size = 16;
    while (size < 2 * keys.size ())
      size *= 2;
    mask_ = size - 1;
    key_.assign (size, kEmpty);
    cell_.resize (size);
    for (std::size_t c = 0; c < keys.size (); ++c)
    {
      std::size_t h = slot (keys[c]);
      while (key_[h] != kEmpty)
        h = (h + 1) & mask_;
      key_[h] = keys[c];
      cell_[h] = static_cast<VertexIndex> (c);
    }
  }

  /** The cell with this code, or -1. */
  std::int64_t
  find (std::uint64_t key) const
  {
    for (std::size_t h = slot (key);; h = (h + 1) & mask_)
    {
      if (key_[h] == key)
        return cell_[h];
      if (key_[h] == kEmpty)
        return -1;
    }
  }

private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t (0);  // no code has 64 bits set

  std::size_t
  slot (std::uint64_t key) const
  {
    return std::size_t ((key * 0x9E3779B97F4A7C15ULL) >> 32) & mask_;
  }

  std::size_t mask_ = 0;
  std::vector<std::uint64_t> key_;
  std::vector<VertexIndex> cell_;
};

} // namespace

namespace {

/** Coarser levels of the octree tried for the points one level leaves unsettled, before
 *  the k-d tree: cells twice as wide take in the k-th neighbour of a point near its
 *  cell's faces, and of most points in sparse regions. */
constexpr int kCoarserLevels = 2;

/** Most points left to the k-d tree that are compared with every point instead: at
 *  1,000,000 points one such comparison took 2 ms, the tree's construction 0.15 s. */
constexpr std::size_t kScannedRest = 16;

/** One level of the curve's octree as a grid: its cells, each a run of consecutive
 *  points, and the search of a point's k nearest among the 27 cells around its own. */
class GridLevel
{
public:
  /** `split[v]`: the level at which point v and the one before it first fall in
   *  different cells (0: the same cell at every level). */
  GridLevel (const PointMatrix &points, const MortonSort &sorted,
             const std::vector<std::uint8_t> &split, int level, std::size_t k,
             std::size_t crowded)
    : points_ (points), grid_ (sorted.grid), k_ (k), crowded_ (crowded)
  {
    const std::size_t n = sorted.codes.size ();
    const int bits = grid_.axis_bits;
    const int shift = 3 * (bits - level);
    for (std::size_t v = 0; v < n; ++v)
      if (v == 0 || (split[v] != 0 && split[v] <= level))
      {
        start_.push_back (static_cast<VertexIndex> (v));
        keys_.push_back (sorted.codes[v] >> shift);
      }
    start_.push_back (static_cast<VertexIndex> (n));
    table_.reset (new CellTable (keys_));
    side_ = std::int64_t (1) << level;
    // When every point coincides (no extent) they share one cell at every level and
    // there are no faces to compare with: the k-d tree takes them all.
    flat_ = !(grid_.scale > 0.0);
    width_ = flat_ ? 0.0 : double (std::uint64_t (1) << (bits - level)) / grid_.scale;
    // How far a point may lie outside its cell's faces as computed here (lo + m width,
    // in double precision): the codes come from (p - lo) scale, rounded otherwise.
    double magnitude = 0.0;
    for (int d = 0; d < 3; ++d)
      magnitude = std::max ({magnitude, std::abs (grid_.lo (d)),
                             std::abs (grid_.lo (d) + double (side_) * width_)});
    face_error_ = 16.0 * DBL_EPSILON * magnitude;
    // The 26 neighbouring cells, nearest first: faces, edges, corners.
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (dx != 0 || dy != 0 || dz != 0)
            around_.push_back ({dx, dy, dz});
    std::stable_sort (around_.begin (), around_.end (), [] (const auto &a, const auto &b) {
      return std::abs (a[0]) + std::abs (a[1]) + std::abs (a[2]) <
             std::abs (b[0]) + std::abs (b[1]) + std::abs (b[2]);
    });
  }

  std::size_t
  numCells () const { return keys_.size (); }

  /** The first point of cell c (numCells() gives the end of the last). */
  VertexIndex
  cellStart (std::size_t c) const { return start_[c]; }

  /** Per-thread buffers of settle(). */
  struct Scratch
  {
    struct Neighbour
    {
      std::size_t begin, end;  // its points among the candidates
      double low[3], high[3];  // its faces
    };
    std::vector<Neighbour> cells;
    std::vector<float> cx, cy, cz, d2;  // the candidates, cell by cell
    std::vector<VertexIndex> cid;
    std::vector<std::uint64_t> within, nearest;
  };

  /** Searches the points of cell c flagged in `unsettled`: writes the k nearest and their
   *  mean distance of each point it settles and clears its flag; leaves the others
   *  flagged. */
  void
  settle (std::size_t c, std::vector<std::uint8_t> &unsettled, VertexIndex *indices,
          double *mean_distances, Scratch &s) const
  {
    const VertexIndex first = start_[c], last = start_[c + 1];
    if (std::find (unsettled.begin () + first, unsettled.begin () + last, 1) ==
        unsettled.begin () + last)
      return;
    if (flat_ || size (c) > crowded_)
      return;
    const std::int64_t cell[3] = {std::int64_t (deinterleave (keys_[c], 0)),
                                  std::int64_t (deinterleave (keys_[c], 1)),
                                  std::int64_t (deinterleave (keys_[c], 2))};
    // The candidates: the cell's own points first, then each neighbour's.
    s.cx.clear ();
    s.cy.clear ();
    s.cz.clear ();
    s.cid.clear ();
    s.cells.clear ();
    const auto gather = [&] (std::size_t other, const std::int64_t *at) {
      Scratch::Neighbour cell_of;
      cell_of.begin = s.cid.size ();
      for (VertexIndex p = start_[other]; p < start_[other + 1]; ++p)
      {
        s.cx.push_back (points_ (p, 0));
        s.cy.push_back (points_ (p, 1));
        s.cz.push_back (points_ (p, 2));
        s.cid.push_back (p);
      }
      cell_of.end = s.cid.size ();
      for (int d = 0; d < 3; ++d)
      {
        cell_of.low[d] = grid_.lo (d) + double (at[d]) * width_;
        cell_of.high[d] = cell_of.low[d] + width_;
      }
      s.cells.push_back (cell_of);
    };
    gather (c, cell);
    for (const auto &offset : around_)
    {
      const std::int64_t at[3] = {cell[0] + offset[0], cell[1] + offset[1], cell[2] + offset[2]};
      if (at[0] < 0 || at[1] < 0 || at[2] < 0 || at[0] >= side_ || at[1] >= side_ ||
          at[2] >= side_)
        continue;
      const std::int64_t other = table_->find (
          interleave (std::uint64_t (at[0]), std::uint64_t (at[1]), std::uint64_t (at[2])));
      if (other < 0)
        continue;
      if (size (std::size_t (other)) > crowded_)
        return;
      gather (std::size_t (other), at);
    }
    if (s.cid.size () <= k_)
      return;
    // A point is settled when its k-th distance is below its distance to every cell
    // outside the 27 (none lies beyond the grid's edges).
    double low[3], high[3];
    for (int d = 0; d < 3; ++d)
    {
      low[d] = cell[d] == 0 ? -std::numeric_limits<double>::infinity ()
                            : grid_.lo (d) + double (cell[d] - 1) * width_;
      high[d] = cell[d] + 1 >= side_ ? std::numeric_limits<double>::infinity ()
                                     : grid_.lo (d) + double (cell[d] + 2) * width_;
    }
    s.d2.resize (s.cid.size ());
    s.within.resize (s.cid.size ());
    s.nearest.resize (k_);
    NearestK best (s.nearest);
    // The guess of the k-th distance: the previous point's of this cell.
    float guess = std::numeric_limits<float>::infinity ();
    for (VertexIndex v = first; v < last; ++v)
    {
      if (!unsettled[v])
        continue;
      const float x = points_ (v, 0), y = points_ (v, 1), z = points_ (v, 2);
      const double q[3] = {x, y, z};
      const std::size_t self = v - first;
      // The squared distance from the point to a cell, less the faces' error.
      const auto gap2 = [&] (const Scratch::Neighbour &cell_of) {
        double sum = 0.0;
        for (int d = 0; d < 3; ++d)
        {
          const double gap = q[d] < cell_of.low[d]    ? cell_of.low[d] - q[d]
                             : q[d] > cell_of.high[d] ? q[d] - cell_of.high[d]
                                                      : 0.0;
          const double shrunk = std::max (0.0, gap - face_error_);
          sum += shrunk * shrunk;
        }
        return sum;
      };
      const auto distances = [&] (const Scratch::Neighbour &cell_of) {
        for (std::size_t j = cell_of.begin; j < cell_of.end; ++j)
        {
          const float ex = x - s.cx[j], ey = y - s.cy[j], ez = z - s.cz[j];
          s.d2[j] = ex * ex + ey * ey + ez * ez;
        }
      };
      // First within the guess, a little wider: the candidates within it, if k or
      // more, hold the k nearest.
      std::size_t found = 0;
      if (guess < std::numeric_limits<float>::infinity ())
        for (std::size_t b = 0; b < s.cells.size (); ++b)
        {
          if (b > 0 && !mayReach (gap2 (s.cells[b]), guess))
            continue;
          distances (s.cells[b]);
          for (std::size_t j = s.cells[b].begin; j < s.cells[b].end; ++j)
          {
            s.within[found] = NearestK::key (s.d2[j], s.cid[j]);
            found += (s.d2[j] <= guess) & (j != self);
          }
        }
      if (found >= k_)
        best.take (s.within.data (), found);
      else
      {
        // Else the own cell, then the neighbours that may hold anything nearer than
        // the k-th so far.
        best.clear ();
        for (std::size_t b = 0; b < s.cells.size (); ++b)
        {
          float worst = best.worst ();
          if (b > 0 && !mayReach (gap2 (s.cells[b]), worst))
            continue;
          distances (s.cells[b]);
          for (std::size_t j = s.cells[b].begin; j < s.cells[b].end; ++j)
            if (s.d2[j] <= worst && j != self)
            {
              best.offer (s.d2[j], s.cid[j]);
              worst = best.worst ();
            }
        }
      }
      if (best.full ())
        guess = best.worst () * kGuessWidening;
      double reach = std::numeric_limits<double>::infinity ();
      for (int d = 0; d < 3; ++d)
        reach = std::min ({reach, q[d] - low[d], high[d] - q[d]});
      reach = std::max (0.0, reach - face_error_);
      if (best.full () && !mayReach (reach * reach, best.worst ()))
      {
        mean_distances[v] = best.write (indices + std::size_t (v) * k_);
        unsettled[v] = 0;
      }
    }
  }

private:
  std::size_t
  size (std::size_t c) const { return std::size_t (start_[c + 1] - start_[c]); }

  const PointMatrix &points_;
  MortonGrid grid_;
  std::size_t k_, crowded_;
  std::vector<VertexIndex> start_;  // the cells: runs of points, start_[c] .. start_[c + 1]
  std::vector<std::uint64_t> keys_;
  std::unique_ptr<CellTable> table_;
  std::int64_t side_ = 0;  // cells per axis
  bool flat_ = false;
  double width_ = 0.0, face_error_ = 0.0;
  std::vector<std::array<int, 3>> around_;
};

} // namespace

void
allNearestOthers (const PointMatrix &points, const MortonSort &sorted, int k, int num_threads,
                  VertexIndex *indices, double *mean_distances, NearestOthersPaths *paths)
{
  NearestOthersPaths counted;
  const std::size_t n = sorted.codes.size ();
  const auto kk = static_cast<std::size_t> (k);
  if (n == 0 || k < 1)
    return;
  const int bits = sorted.grid.axis_bits;

  // Level at which each point and the previous one first fall in different cells: that
  // of their codes' highest differing bit (0: the same cell at every level).
  std::vector<std::uint8_t> split (n, 0);
  parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t v = std::max<std::size_t> (begin, 1); v < end; ++v)
    {
      const std::uint64_t diff = sorted.codes[v] ^ sorted.codes[v - 1];
      if (diff != 0)
        split[v] = static_cast<std::uint8_t> (bits - (63 - __builtin_clzll (diff)) / 3);
    }
  });
  // The grid's level: the finest at which half the points or more lie in cells of at
  // least `occupancy` points (the median point's cell: outliers in cells of their own
  // do not make it coarser).
  const std::size_t occupancy = std::max<std::size_t> (kMinOccupancy, kOccupancyPerNeighbour * kk);
  const auto inFullCells = [&] (int level) {  // the points in cells of `occupancy` or more
    std::size_t count = 0, run = 0;
    for (std::size_t v = 0; v < n; ++v)
    {
      if (v > 0 && split[v] != 0 && split[v] <= level)
      {
        count += run >= occupancy ? run : 0;
        run = 0;
      }
      ++run;
    }
    return count + (run >= occupancy ? run : 0);
  };
  int level = 0;
  for (int coarse = 1, fine = bits; coarse <= fine;)
  {
    const int middle = (coarse + fine) / 2;
    if (2 * inFullCells (middle) >= n)
      level = middle, coarse = middle + 1;
    else
      fine = middle - 1;
  }

  // The grid settles most points; the points it leaves (whose k-th neighbour may lie
  // beyond the 27 cells) are searched again on coarser grids, and the rest (in crowded
  // cells, or still unsettled) by comparison with every point if few, else in the k-d
  // tree.
  std::vector<std::uint8_t> unsettled (n, 1);
  std::size_t left = n;
  for (int pass = 0; pass <= kCoarserLevels && level - pass >= 0 && left > 0; ++pass)
  {
    const std::size_t before = left;
    const GridLevel grid (points, sorted, split, level - pass, kk, kCrowdedCell * occupancy);
    parallelFor (
        grid.numCells (), num_threads,
        [&] (std::size_t first_cell, std::size_t last_cell) {
          GridLevel::Scratch scratch;
          for (std::size_t c = first_cell; c < last_cell; ++c)
            grid.settle (c, unsettled, indices, mean_distances, scratch);
        },
        64);
    left = static_cast<std::size_t> (std::count (unsettled.begin (), unsettled.end (), 1));
    (pass == 0 ? counted.grid : counted.coarser) += before - left;
    if (pass > 0 && left == before)
      break;  // a coarser level settles no more
  }
  std::vector<std::uint8_t> ().swap (split);

  std::vector<VertexIndex> rest;
  for (std::size_t v = 0; v < n; ++v)
    if (unsettled[v])
      rest.push_back (static_cast<VertexIndex> (v));
  (rest.size () <= kScannedRest ? counted.scanned : counted.tree) = rest.size ();
  if (paths)
    *paths = counted;
  if (rest.empty ())
    return;
  if (rest.size () <= kScannedRest)
  {
    // A few: compared with every point, rather than a k-d tree built for them.
    parallelFor (
        rest.size (), num_threads,
        [&] (std::size_t begin, std::size_t end) {
          std::vector<std::uint64_t> keys (kk);
          NearestK best (keys);
          for (std::size_t r = begin; r < end; ++r)
          {
            const VertexIndex v = rest[r];
            const float x = points (v, 0), y = points (v, 1), z = points (v, 2);
            best.clear ();
            for (std::size_t j = 0; j < n; ++j)
            {
              const float ex = x - points (j, 0), ey = y - points (j, 1), ez = z - points (j, 2);
              if (j != v)
                best.offer (ex * ex + ey * ey + ez * ez, static_cast<VertexIndex> (j));
            }
            mean_distances[v] = best.write (indices + std::size_t (v) * kk);
          }
        },
        1);
    return;
  }
  const KdTree tree (points);
  parallelFor (
      rest.size (), num_threads,
      [&] (std::size_t begin, std::size_t end) {
        std::vector<std::uint64_t> scratch;
        for (std::size_t r = begin; r < end; ++r)
        {
          const VertexIndex v = rest[r];
          mean_distances[v] =
              tree.nearestOthersExact (v, k, indices + std::size_t (v) * kk, scratch);
        }
      },
      256);
}

namespace {

/** Points whose mean distance to their nearest others exceeds this many times the
 *  median's are left out of the spacing: isolated far points. */
constexpr double kFarSpacings = 50.0;

} // namespace

double
meanSpacing (const std::vector<double> &means)
{
  if (means.empty ())
    return 0.0;
  std::vector<double> sorted (means);
  const auto middle = sorted.begin () + std::ptrdiff_t (sorted.size () / 2);
  std::nth_element (sorted.begin (), middle, sorted.end ());
  const double cut = *middle > 0.0 ? kFarSpacings * *middle
                                   : std::numeric_limits<double>::infinity ();
  double sum = 0.0;
  std::size_t count = 0;
  for (const double m : means)
    if (m <= cut)
    {
      sum += m;
      ++count;
    }
  return count > 0 ? sum / double (count) : 0.0;
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise
