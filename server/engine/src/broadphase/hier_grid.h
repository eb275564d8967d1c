#pragma once
// Broadphase for movable bodies: a hierarchical uniform grid rebuilt every tick by sorting.
//
// Why sorting instead of a hash table: a stable radix sort of (row-major cell key, body) gives a
// deterministic, spatially coherent body order for free (the solver gathers its working arrays in
// that order, so neighbours sit next to each other in memory), and neighbour cells in the next row
// are found by a pointer that only moves forward. Cost is O(N) per tick with no allocation after
// warm-up.
//
// Why levels: with one cell size, a 4x larger giant forces 16x larger cells and every foot soldier
// then tests 16x more candidates. Each body goes to the smallest level whose cell is at least its
// diameter plus margin; same-level pairs use a half stencil, cross-level pairs are found by the
// larger body querying the finer levels over its box.
//
// Why a candidate cap: 10,000 bodies started at one point all share a cell; testing all pairs is
// O(N^2). Each body examines at most max_candidates neighbours per tick (in sorted order), which
// keeps the cost linear; the solver then spreads the pile out over a few ticks and the cap stops
// binding.
#include <cstdint>
#include <vector>

#include "broadphase/radix_sort.h"
#include "throng/core/worker_pool.h"

namespace throng::detail {

struct CandidatePair {
  // The default constructor leaves a and b unset on purpose: find_pairs grows its output ahead of
  // use (resize costs nothing then) and writes every tested pair, keeping only the hits.
  CandidatePair() {}
  CandidatePair(std::uint32_t a_, std::uint32_t b_) : a(a_), b(b_) {}
  std::uint32_t a;  // solver index (position in order())
  std::uint32_t b;
};

struct GridBodyView {  // arrays in solver order
  const double* x;
  const double* y;
  const double* z;
  const double* r;
  const double* hh;
  const std::uint32_t* group;
  const std::uint32_t* mask;
};

// The pair test's inputs and which tests it makes (defined in hier_grid.cpp).
struct GridScanBodies;
enum class GridTestMode;

class HierGrid {
 public:
  static constexpr int kMaxLevels = 12;

  // Assigns levels and sorts. x, y, r are in dense order; afterwards order()[s] is the dense index
  // of solver slot s. cell0_m is the finest cell edge.
  void build(const double* x, const double* y, const double* r, std::size_t n, double margin_m, double cell0_m);
  const std::vector<std::uint32_t>& order() const { return order_; }

  // Calls f(begin, end) with the solver index range of every finest-level cell holding more than
  // `threshold` bodies, in key order.
  template <class F>
  void for_each_crowded_cell(std::uint32_t threshold, F&& f) const {
    if (level_count_ == 0) return;
    for (const Cell& c : levels_[0].cells) {
      if (c.end - c.begin > threshold) f(c.begin, c.end);
    }
  }

  // The solver order is level by level, finest first: level l holds solver indices
  // [level_begin(l), level_begin(l + 1)), and level_begin(level_count()) is the body count.
  int level_count() const { return level_count_; }
  std::uint32_t level_begin(int l) const {
    return l < level_count_ ? levels_[static_cast<std::size_t>(l)].begin : static_cast<std::uint32_t>(order_.size());
  }

  // Appends all candidate pairs (a < b not required; each unordered pair appears once) in a
  // deterministic order: finest level first, in row-major cell order. Returns the number of bodies
  // whose candidate budget ran out. margin_m may exceed the build's margin by up to
  // max_extra_margin(cell0_m, build margin) (a pair list's skin): the search then reaches two
  // cells out instead of one.
  // With a pool, the search is cut into runs of cells (and of coarser bodies), each scanned into
  // its own buffer on the pool's threads and appended in order: the same output.
  // In two parts (a pair list searched across a tick boundary): kFirst scans the finest level's
  // cells holding its first `first_share` of all bodies, kRest (on the same grid and bodies,
  // nothing built in between) appends the others; together they append exactly what kAll appends,
  // and the budgets they report add up to its.
  enum class SearchPart { kAll, kFirst, kRest };
  std::uint32_t find_pairs(const GridBodyView& v, double margin_m, std::uint32_t max_candidates,
                           std::vector<CandidatePair>& out, WorkerPool* pool = nullptr,
                           SearchPart part = SearchPart::kAll, double first_share = 0.5);
  // How much wider than the build's margin a search may reach with two cells: a body of level l
  // has 2 (r + margin) <= cell_l, so its widest pair 2 r + margin + extra stays within 2 cell_l
  // while extra <= cell_l + margin, and cell_l >= cell0.
  static double max_extra_margin(double cell0_m, double margin_m) { return cell0_m + margin_m; }

 private:
  // find_pairs' phases (hier_grid.cpp): the pairs within a counting-sorted level, within a sorted
  // (sparse) level, and of each coarser body with the finer levels' bodies, all into one PairScan
  // (the output and the budgets) for the pair test the bodies need.
  template <GridTestMode kMode>
  class PairScan;
  struct Level;
  template <GridTestMode kMode>
  std::uint32_t find_pairs_in_mode(const GridScanBodies& a, double margin, double extra, std::uint32_t max_candidates,
                                   std::vector<CandidatePair>& out, WorkerPool* pool, SearchPart part,
                                   double first_share);
  // The pieces of the whole search, cut after the finest level's cell that holds body
  // `first_share` of all when `split`.
  void cut_pieces(bool on_pool, bool split, double first_share);
  // One piece of the search: cells [begin, end) of level l, or (cross) the bodies [begin, end) of
  // coarser level l against the finer levels.
  struct SearchPiece {
    int level;
    bool cross;
    std::uint32_t begin, end;
  };
  template <class Scan>
  void scan_piece(const SearchPiece& piece, int reach_cells, double extra, Scan& scan) const;
  template <class Scan>
  void scan_indexed_level(const Level& lv, std::uint32_t c0, std::uint32_t c1, int reach_cells, int top_reach,
                          Scan& scan) const;
  template <class Scan>
  void scan_sorted_level(const Level& lv, std::uint32_t c0, std::uint32_t c1, int reach_cells, int top_reach,
                         Scan& scan) const;
  template <class Scan>
  void scan_cross_levels(int l, std::uint32_t i0, std::uint32_t i1, double extra, Scan& scan) const;
  // The pieces of a search on a pool; each thread appends its pieces' candidates to its own buffer
  // (kept with room for twice the largest search so far, so that a tick does not allocate), and
  // each piece records where in which buffer its candidates are, and how many bodies it capped.
  std::vector<SearchPiece> pieces_;
  std::size_t rest_begin_ = 0;   // the first piece of a kRest part
  bool rest_pending_ = false;    // a kFirst part was scanned on this grid and its rest was not
  std::vector<std::vector<CandidatePair>> thread_out_;
  struct PieceOut {
    std::uint32_t thread;
    std::size_t begin, end;
    std::uint32_t capped;
  };
  std::vector<PieceOut> piece_out_;
  std::size_t largest_search_ = 0;

  struct Cell {
    Cell() {}  // unset: build() sizes the cell list ahead and keeps only the occupied cells
    Cell(std::uint64_t key_, std::uint32_t begin_, std::uint32_t end_) : key(key_), begin(begin_), end(end_) {}
    std::uint64_t key;
    std::uint32_t begin;  // solver index range [begin, end)
    std::uint32_t end;
  };
  // Keys are row-major and dense over the level's occupied box plus a one-cell empty border:
  // key = (cy - min_cy + 1) * stride + (cx - min_cx + 1). Small keys need only 2-3 radix passes
  // (a crowd of 20,000 spans ~140 x 140 cells: keys below 2^16), the right neighbour is key + 1 and
  // the row above is key + stride, and the empty border keeps cx - 1 / cx + 1 from wrapping into
  // another row.
  struct Level {
    std::int64_t min_cx = 0, min_cy = 0;
    std::uint64_t stride = 1;  // cells per row including the border
    std::uint64_t rows = 1;    // rows including the border
    double cell_m = 0.0;
    double max_reach_m = 0.0;  // largest r + margin of a body at this level
    std::uint32_t begin = 0, end = 0;  // solver index range of the level
    std::vector<Cell> cells;
    // When the level's key range is small next to its body count (any crowd), the level is sorted
    // by counting and start[k] is the first solver index of key k (start[k + 1] its end), for every
    // key of the level: find_pairs then finds neighbour cells by index. Empty otherwise (sparse
    // levels are radix-sorted).
    std::vector<std::uint32_t> start;
  };

  // Key of cell (cx, cy) of a level; coordinates outside the level's box are clamped onto its
  // empty border, which is what range queries from coarser levels want.
  static std::uint64_t level_key(const Level& lv, std::int64_t cx, std::int64_t cy);
  // Sorts the m bodies of a level (cell coordinates cxy, dense indices idx or, if null, 0..m-1,
  // in dense order) into order_[lv.begin, lv.end) and builds lv.cells (and lv.start).
  void sort_level(Level& lv, const std::int32_t* cxy, const std::uint32_t* idx, std::uint32_t m, std::int64_t min_cx,
                  std::int64_t min_cy, std::int64_t max_cx, std::int64_t max_cy);
  std::vector<std::int32_t> coords_;  // cx, cy per body of the level being built (cell_coord fits 32 bits)
  std::vector<std::uint32_t> level_index_;  // dense index per body of the level being built
  std::vector<std::uint32_t> keys_;   // cell key per body of the level being built (counting sort)

  std::vector<Level> levels_;
  int level_count_ = 0;
  double build_margin_m_ = 0.0;
  std::vector<std::uint32_t> order_;
  std::vector<KeyIndex> items_, scratch_;
  std::vector<std::uint8_t> level_of_;
};

}  // namespace throng::detail
