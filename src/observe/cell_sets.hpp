#pragma once
/// The per-hit work of observe after Embree's rtcIntersect (issues 45 and 47): a hit point's cell
/// with a multiply instead of three divisions, and the cells of one candidate's hits split by R
/// with a shared hash of R's keys and per-worker marks over R, instead of sorting every image's
/// keys. Both give exactly what VoxelKeyOf and a sort + merge against R give.
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "vantage/reference.hpp"
#include "vantage/types.hpp"
#include "vantage/visibility.hpp"

namespace vantage::detail {

/// floor(x / F) as VoxelKeyOf computes it (FloorToInt of the rounded quotient), from x · (1/F).
///
/// Why the answer is the same: 1/F, x · (1/F) and x / F are each rounded once (relative error at
/// most u = 2^-53 while the results are normal), so the product q and the quotient d differ by
/// less than 4u·|q|. When q lies farther than that from every integer, no integer lies between q
/// and d or on d, so floor(q) = floor(d). Otherwise (q within |q|·2^-50 + 2^-1000 of an integer:
/// a point on or next to a cell boundary, or a subnormal, infinite or NaN quotient) the division
/// itself decides. A cell size whose reciprocal is not a normal double always divides.
class CellOfPoint {
 public:
  explicit CellOfPoint(double cell_size)
      : cell_(cell_size),
        inverse_(1.0 / cell_size),
        divide_(!std::isnormal(cell_size) || !std::isnormal(1.0 / cell_size)) {}

  int64_t Axis(double x) const {
    if (divide_) return FloorToInt(x / cell_);
    const double q = x * inverse_;
    const int64_t k = FloorToInt(q);
    const double below = static_cast<double>(k);
    const double margin = std::abs(q) * 0x1p-50 + 0x1p-1000;
    // Both differences are exact where they decide (Sterbenz, or a fraction of q's own bits).
    if (q - below > margin && below + 1.0 - q > margin) return k;
    return FloorToInt(x / cell_);
  }
  VoxelIndex operator()(const Vec3& p) const { return {Axis(p.x()), Axis(p.y()), Axis(p.z())}; }

  /// Axis(x), trying `guess` (a neighbouring hit's index, |guess| < 2^53 so that it converts
  /// exactly) first: where q = x · (1/F) lies in
  /// (guess, guess + 1) by more than Axis's margin, guess is floor(q) and Axis's own test passes
  /// with it, so Axis would return it; otherwise Axis decides. A guess outside (q - 1, q + 1)
  /// fails the test: q - guess or guess + 1 - q is then at most 0 however it rounds. Saves the
  /// floor (and its sign-dependent branch) for the hits that stay in their neighbour's cell.
  int64_t Axis(double x, int64_t guess) const { return Axis(x, guess, static_cast<double>(guess)); }
  /// Axis(x, guess) with the guess also as a double (`below`, its exact conversion), kept by a
  /// caller that tries the same guess on many hits.
  int64_t Axis(double x, int64_t guess, double below) const {
    const double q = x * inverse_;
    const double margin = std::abs(q) * 0x1p-50 + 0x1p-1000;
    if (!divide_ && q - below > margin && below + 1.0 - q > margin) return guess;
    return Axis(x);
  }
  /// The cell of `p`, trying `guess`'s index on each axis (Axis(x, guess)).
  VoxelIndex Near(const Vec3& p, const VoxelIndex& guess) const {
    return {Axis(p.x(), guess[0]), Axis(p.y(), guess[1]), Axis(p.z(), guess[2])};
  }
  /// Near with `below` the guess's indices as doubles (exact conversions, see Axis).
  VoxelIndex Near(const Vec3& p, const VoxelIndex& guess, const std::array<double, 3>& below) const {
    return {Axis(p.x(), guess[0], below[0]), Axis(p.y(), guess[1], below[1]),
            Axis(p.z(), guess[2], below[2])};
  }

 private:
  double cell_, inverse_;
  bool divide_;
};

/// PackVoxel without its own range check (the caller has checked VoxelIndexFits).
inline uint64_t PackFittingVoxel(const VoxelIndex& index) {
  const auto axis = [](int64_t v) { return static_cast<uint64_t>(v + kVoxelAxisOffset); };
  return (axis(index[0]) << 42) | (axis(index[1]) << 21) | axis(index[2]);
}

/// R's keys in a flat open-addressing table (linear probing, at most two thirds full): a packed
/// key's index in Reference::keys, or -1. Built once per Observe call and read by every worker.
class CellIndex {
 public:
  explicit CellIndex(const std::vector<uint64_t>& keys);
  int64_t Find(uint64_t key) const {
    for (size_t slot = Slot(key);; slot = (slot + 1) & mask_) {
      const uint64_t k = keys_[slot];
      if (k == key) return indices_[slot];
      if (k == kEmpty) return -1;
    }
  }
  size_t size() const { return size_; }
  /// Bytes the table holds for `reference_size` keys (EstimateMemory).
  static uint64_t Bytes(size_t reference_size);

 private:
  // Packed keys use 63 bits, so no key is all ones.
  static constexpr uint64_t kEmpty = ~uint64_t{0};
  static size_t Capacity(size_t size);
  size_t Slot(uint64_t key) const {
    return static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> shift_) & mask_;
  }
  std::vector<uint64_t> keys_;
  std::vector<uint32_t> indices_;
  size_t mask_ = 0;
  int shift_ = 64;
  size_t size_ = 0;
};

/// The cells of one candidate's hits (one of its sets: every measured pixel, those passing the
/// quality filter, those the ideal pinhole counts), kept as marks over R: a bit per cell of R,
/// the pixels of each marked cell when counting, the marked indices in the order first met, and
/// the keys not in R. The marks are cleared by Take, through the touched list, so one CellSet
/// serves every candidate a worker observes. Consecutive hits in one cell (neighbouring pixels)
/// cost one comparison.
class CellSet {
 public:
  /// Sized for `index`'s R (grows on first use, keeps its memory after).
  void Reset(const CellIndex& index, bool count);

  /// One pixel whose hit lies in the cell `key`.
  void Add(uint64_t key) {
    if (key == last_key_) {
      if (last_index_ >= 0 && count_) Bump(static_cast<size_t>(last_index_));
      return;
    }
    Add(key, index_->Find(key));
  }
  /// Add, with the key's index in R already found (`found`: the index's Find(key)), so that
  /// several sets fed the same hits look each cell up once.
  void Add(uint64_t key, int64_t found) {
    if (key == last_key_) {
      if (last_index_ >= 0 && count_) Bump(static_cast<size_t>(last_index_));
      return;
    }
    last_key_ = key;
    last_index_ = found;
    if (last_index_ < 0) {
      outside_.push_back(key);
      return;
    }
    const size_t i = static_cast<size_t>(last_index_);
    uint64_t& word = marks_[i >> 6];
    const uint64_t bit = uint64_t{1} << (i & 63);
    if (!(word & bit)) {
      word |= bit;
      touched_.push_back(static_cast<uint32_t>(i));
    }
    if (count_) Bump(i);
  }

  /// R's indices of the cells, ascending, to `indices`; their pixels (saturated at
  /// kMaxPointCount) to `hits` when counting and `hits` is not null; the keys not in R, ascending
  /// and unique, to `outside` (may be null). Clears the marks for the next candidate. The same
  /// lists as sorting the keys and merging them with R's.
  void Take(std::vector<uint32_t>* indices,
            std::vector<uint16_t>* hits,
            std::vector<uint64_t>* outside);

  /// Bytes a worker's set holds for R of `reference_size` cells and an image of `pixels`
  /// (EstimateMemory): the marks, the counts when counting, the touched list and outside keys at
  /// their worst.
  static uint64_t Bytes(size_t reference_size, uint64_t pixels, bool count);

 private:
  void Bump(size_t i) {
    if (counts_[i] != kMaxPointCount) ++counts_[i];
  }
  const CellIndex* index_ = nullptr;
  bool count_ = false;
  uint64_t last_key_ = ~uint64_t{0};
  int64_t last_index_ = -1;
  std::vector<uint64_t> marks_;
  std::vector<uint16_t> counts_;
  std::vector<uint32_t> touched_;
  std::vector<uint64_t> outside_;
};

/// A worker's sets: every measured pixel, those passing the quality filter, those the ideal
/// pinhole counts (see PixelJudge).
struct CellSets {
  CellSet all, quality, ideal;
};

/// Per-worker CellSets, lent for one candidate at a time: a candidate takes one from the pool
/// (made when none is free) and gives it back when done, so a worker thread that picks up another
/// candidate while it waits inside Embree (a BVH build may run on TBB) gets its own.
class CellSetsPool {
 public:
  class Lease {
   public:
    explicit Lease(CellSetsPool* pool);
    ~Lease();
    Lease(const Lease&) = delete;
    Lease& operator=(const Lease&) = delete;
    CellSets& operator*() const { return *sets_; }
    CellSets* operator->() const { return sets_.get(); }

   private:
    CellSetsPool* pool_;
    std::unique_ptr<CellSets> sets_;
  };

 private:
  std::mutex mutex_;
  std::vector<std::unique_ptr<CellSets>> free_;
};

}  // namespace vantage::detail
