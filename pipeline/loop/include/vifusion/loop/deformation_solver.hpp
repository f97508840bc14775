#pragma once
// The linear algebra of the deformation graph's Gauss-Newton solver: symmetric normal equations
// H·δ = −b with 12×12 blocks (one block row/column per node) on a block pattern given per solve, solved by
// a hand-written sparse block LDLᵀ factorisation that never allocates after construction.
//
// Lifecycle: the constructor allocates everything for a BlockSparseCapacity. setPattern() once per graph
// and constraint set — it deduplicates and sorts the block pattern and runs the symbolic analysis
// (elimination tree, column counts, factor layout). Then per Gauss-Newton iteration: setZero(),
// addBlock()/addGradient() for every residual, solve().
//
// Memory: only the constructor allocates. setPattern(), setZero(), addBlock(), addGradient() and solve()
// never do, on any pattern; a pattern that does not fit the capacity makes setPattern() return false (and
// solve() return false until a pattern that fits is set) — nothing overflows, nothing grows. With
// N = max_blocks, P = max_pattern_blocks and F = (max_factor_nonzeros − 66·N)/144 off-diagonal factor
// blocks, the memory is about
//   1152·(P + F + 2·N) bytes (12×12 double blocks: H's pattern blocks, L's off-diagonal blocks, L's diagonal
//   blocks with D, the triangular solve's work column) + 12·P + 4·F + 128·N bytes (indices, b),
// e.g. 53 MB for the deformation graph's defaults (1024 nodes, band 19 and its E_rel reserve: P = 20 370,
// F = 23 358).
//
// Why hand-written: Eigen 3.4's SimplicialLDLT has no allocation-free entry point (analyzePattern()
// allocates the pattern and ordering, every factorize() a permuted copy of H and work arrays), and CHOLMOD
// would add a dependency to the arm64 cross-build and also allocates per factorisation. The factorisation is
// the textbook up-looking sparse LDLᵀ (row by row: a sparse triangular solve over the row's elimination-tree
// reach), done on 12×12 blocks with fixed-size Eigen kernels; block rows share one scalar pattern, so the
// symbolic analysis (elimination tree with path compression, column counts) runs on the block pattern.
//
// Ordering: natural (node index = creation time), no fill-reducing permutation. The graph's nodes are
// sorted by time, E_reg couples each node to its neighbours_per_side temporal neighbours and E_con/E_pin
// bind a point to nodes inside a window of `candidates` consecutive nodes, so H lies inside a band of
// max(neighbours_per_side, candidates − 1) blocks; the elimination of a banded matrix in natural order fills
// only inside the band (the elimination tree is a path). On a synthetic pattern like the loop closure's
// (1024 nodes, 4 per side, 1536 points in windows of 20) it gives 8 % more factor blocks and 17 % more
// flops than Eigen's AMD. The factorisation costs about 864·Σ_j c_j² multiply-adds (c_j: blocks in L's
// column j, ≤ the band). The exception is E_rel between two windows far apart in time: block row j of L
// then fills back to the other window (at most j blocks per row). The owner sizes the capacity for the
// band (BlockSparseCapacity::band) plus a reserve; what exceeds it fails cleanly.
//
// Numerics: H is positive semi-definite (a sum of JᵀJ·ω); damping·I (and λ·diag(H)) make it positive definite
// in the directions no term constrains. Every pivot d of D is checked: d ≤ 0 or not finite → solve() returns
// false (H + damping·I was not positive definite: a wrong Jacobian, a NaN, or damping = 0 on a free
// direction). A tiny positive pivot is accepted; the step is then checked for finiteness.

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "vifusion/loop/deformation_function.hpp"

namespace vifusion::loop {

using Matrix12d = Eigen::Matrix<double, kNodeParamDim, kNodeParamDim>;
using Vector12d = Eigen::Matrix<double, kNodeParamDim, 1>;

/// What a BlockSparseSystem can hold, fixed at construction.
struct BlockSparseCapacity {
  /// Scalar entries of L strictly below the diagonal inside one 12×12 diagonal block: 12·11/2.
  static constexpr std::int64_t kDiagonalBlockNonzeros = kNodeParamDim * (kNodeParamDim - 1) / 2;
  /// Scalar entries of one 12×12 off-diagonal block.
  static constexpr std::int64_t kBlockNonzeros = kNodeParamDim * kNodeParamDim;

  int max_blocks = 0;                    ///< block rows (nodes) N, ≥ 0
  std::int64_t max_pattern_blocks = 0;   ///< distinct upper-triangle blocks, diagonal included; ≥ N to be usable
  std::int64_t max_factor_nonzeros = 0;  ///< scalar entries of L strictly below its unit diagonal

  /// Factor nonzeros of a pattern whose L has `off_diagonal_blocks` blocks below the block diagonal over
  /// `blocks` block rows: 144 per off-diagonal block plus 66 inside each diagonal block.
  static std::int64_t factorNonzeros(std::int64_t blocks, std::int64_t off_diagonal_blocks) {
    return kBlockNonzeros * off_diagonal_blocks + kDiagonalBlockNonzeros * blocks;
  }
  /// The exact worst case of any pattern inside a band |i − j| ≤ band_blocks on max_blocks blocks, in
  /// natural ordering (L fills at most the band): N + N·w − w(w+1)/2 pattern blocks, w = min(band, N − 1).
  static BlockSparseCapacity band(int max_blocks, int band_blocks);
};

class BlockSparseSystem {
 public:
  /// Capacity 0: only the empty pattern fits. For members that are assigned a sized one later.
  BlockSparseSystem() : BlockSparseSystem(BlockSparseCapacity{}) {}
  /// Allocates everything for `capacity` (the only allocation of this class).
  /// @throws vifusion::Error when a capacity is negative or beyond the int block indices.
  explicit BlockSparseSystem(const BlockSparseCapacity& capacity);

  const BlockSparseCapacity& capacity() const { return capacity_; }

  /// Fixes the pattern: `block_count` nodes, and the node pairs (i, j) whose block H_ij may be non-zero
  /// (either order, duplicates allowed; the diagonal blocks are always present), then runs the symbolic
  /// analysis. Never allocates. Returns false — leaving no usable pattern: blockCount() 0, addBlock() and
  /// addGradient() ignored, solve() false — when block_count exceeds max_blocks, a node index is outside
  /// [0, block_count), the distinct blocks exceed max_pattern_blocks or L would exceed max_factor_nonzeros.
  bool setPattern(int block_count, std::span<const std::pair<int, int>> pairs);

  int blockCount() const { return block_count_; }
  /// Number of distinct upper-triangle blocks, diagonal included.
  int patternBlocks() const { return pattern_blocks_; }
  /// Scalar nonzeros of L strictly below its diagonal for the current pattern (0 without one).
  std::int64_t factorNonzeros() const;

  /// Zeroes H and b.
  void setZero();
  /// H_ij += H_block, where H_block = ∂r/∂x_iᵀ·∂r/∂x_j·ω (i and j in either order: the transpose goes to
  /// the upper triangle). The pair must be in the pattern (asserted in debug builds).
  void addBlock(int i, int j, const Matrix12d& H_block);
  /// b_i += b_block.
  void addGradient(int i, const Vector12d& b_block);

  /// Solves (H + λ·diag(H) + damping·I)·δ = −b into delta (size 12·blockCount()): Gauss-Newton for λ = 0,
  /// Levenberg-Marquardt otherwise; H's diagonal is read from the upper triangle of its diagonal blocks.
  /// Returns false, leaving delta unspecified, without a valid pattern, when delta has the wrong size, a
  /// pivot is ≤ 0 or not finite, or δ is not finite. Never allocates. May be called again with another λ
  /// without re-adding the blocks.
  bool solve(double damping, double lambda, Eigen::Ref<Eigen::VectorXd> delta);

 private:
  /// Index of block (i, j), i ≤ j, in the pattern (sorted by column j, then row i).
  int blockIndex(int i, int j) const;
  /// Inserts (i, j), i ≤ j, into column j's list unless present; false when the capacity is exhausted.
  bool insertPair(int i, int j);
  /// Elimination tree, column counts and factor layout of the sorted pattern; false when L does not fit.
  bool analyse();
  /// Writes block row k's reach in the elimination tree (the block pattern of L's row k) into
  /// reach_[top … block_count_) in topological order (descendants first) and returns top.
  int rowReach(int k);
  /// Numeric factorisation of H + λ·diag(H) + damping·I into factor_off_ and factor_diag_.
  bool factorize(double damping, double lambda);

  BlockSparseCapacity capacity_;
  int max_factor_blocks_ = 0;  ///< off-diagonal blocks of L that fit
  int block_count_ = 0;
  int pattern_blocks_ = 0;
  int factor_blocks_ = 0;  ///< off-diagonal blocks of L for the current pattern
  bool valid_ = false;     ///< a pattern that fits is set

  // Pattern (upper triangle of H by block column).
  std::vector<int> list_head_;       ///< setPattern scratch: first list entry of column j, −1 = none; size N
  std::vector<int> list_next_;       ///< setPattern scratch: next entry of the same column; size P
  std::vector<int> list_row_;        ///< setPattern scratch: row i of the entry; size P
  std::vector<int> column_begin_;    ///< first pattern index of block column j; size N + 1
  std::vector<int> pattern_row_;     ///< row i of each pattern block, sorted within a column; size P
  std::vector<Matrix12d> blocks_;    ///< H blocks in pattern order (the diagonal block last in its column)
  std::vector<Vector12d> gradient_;  ///< b per node

  // Symbolic factor.
  std::vector<int> parent_;        ///< elimination tree: parent of block column j, −1 for a root; size N
  std::vector<int> flag_;          ///< traversal marks (row being processed); size N
  std::vector<int> reach_;         ///< row reach in topological order (filled from the end); size N
  std::vector<int> path_;          ///< rowReach scratch: one upward path; size N
  std::vector<int> factor_begin_;  ///< first off-diagonal block of L's column j; size N + 1
  std::vector<int> factor_fill_;   ///< blocks of L's column j written so far in factorize(); size N

  // Numeric factor: L's off-diagonal blocks L(i, j), i > j, by column in increasing row i; per node the
  // diagonal block with L's unit lower triangle strictly below its diagonal and D on it.
  std::vector<int> factor_row_;         ///< row i of each off-diagonal block; size F
  std::vector<Matrix12d> factor_off_;   ///< size F
  std::vector<Matrix12d> factor_diag_;  ///< size N
  std::vector<Matrix12d> work_;         ///< triangular-solve column W_i = D_i·L(k, i)ᵀ of the row k; size N
};

}  // namespace vifusion::loop
