#pragma once
// The linear algebra of the deformation graph's Gauss-Newton solver: symmetric normal equations
// H·δ = −b with 12×12 blocks (one block row/column per node) on a block pattern fixed in advance.
//
// Lifecycle: setPattern() once per graph and constraint set — it sorts the block pattern, lays out the
// upper triangle of H as an Eigen::SparseMatrix (compressed column) and runs the symbolic analysis
// (AMD ordering, elimination tree) of SimplicialLDLT. Then per Gauss-Newton iteration: setZero(),
// addBlock()/addGradient() for every residual, solve(). Eigen's Simplicial solvers, not CHOLMOD: the
// library cross-builds for arm64 with Eigen alone.
//
// Memory: setPattern() allocates (pattern, matrix, block store, symbolic factorisation). setZero(),
// addBlock() and addGradient() never allocate. solve() does: Eigen's SimplicialLDLT::factorize() builds a
// permuted copy of H and O(n) work arrays (on the heap once they pass Eigen's stack limit) on every call;
// there is no allocation-free entry point in Eigen 3.4. Deformation is an event (a loop closure), not
// the per-frame path, so this is accepted and documented rather than worked around.

#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "vifusion/loop/deformation_function.hpp"

namespace vifusion::loop {

using Matrix12d = Eigen::Matrix<double, kNodeParamDim, kNodeParamDim>;
using Vector12d = Eigen::Matrix<double, kNodeParamDim, 1>;

class BlockSparseSystem {
 public:
  /// Fixes the pattern: `block_count` nodes, and the node pairs (i, j) whose block H_ij may be non-zero
  /// (either order, duplicates allowed; the diagonal blocks are always present). Allocates.
  void setPattern(int block_count, std::span<const std::pair<int, int>> pairs);

  int blockCount() const { return block_count_; }
  /// Number of distinct upper-triangle blocks, diagonal included.
  int patternBlocks() const { return static_cast<int>(pairs_.size()); }

  /// Zeroes H and b.
  void setZero();
  /// H_ij += H_block, where H_block = ∂r/∂x_iᵀ·∂r/∂x_j·ω (i and j in either order: the transpose goes to
  /// the upper triangle). The pair must be in the pattern (asserted in debug builds).
  void addBlock(int i, int j, const Matrix12d& H_block);
  /// b_i += b_block.
  void addGradient(int i, const Vector12d& b_block);

  /// Solves (H + λ·diag(H) + damping·I)·δ = −b into delta (size 12·blockCount()): Gauss-Newton for λ = 0,
  /// Levenberg-Marquardt otherwise. Returns false, leaving delta unspecified, when the factorisation fails
  /// or δ is not finite. May be called again with another λ without re-adding the blocks.
  bool solve(double damping, double lambda, Eigen::Ref<Eigen::VectorXd> delta);

 private:
  /// Index of block (i, j), i ≤ j, in pairs_ (sorted by column j, then row i).
  int blockIndex(int i, int j) const;

  int block_count_ = 0;
  std::vector<std::pair<int, int>> pairs_;  ///< (row i, column j), i ≤ j, sorted by (j, i)
  std::vector<int> column_begin_;           ///< first pairs_ index of block column j; size block_count_ + 1
  std::vector<Matrix12d> blocks_;           ///< H blocks, same order as pairs_
  std::vector<std::int64_t> value_offset_;  ///< per block and column c: index of its first value in H_
  Eigen::VectorXd b_;
  Eigen::SparseMatrix<double> H_;  ///< upper triangle
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Upper> ldlt_;
  bool analysed_ = false;
};

}  // namespace vifusion::loop
