#include "vifusion/loop/deformation_solver.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/resident_memory.hpp"

namespace vifusion::loop {
namespace {

constexpr int kB = kNodeParamDim;
constexpr std::int64_t kMaxIndex = std::numeric_limits<int>::max();  // block indices are int
constexpr int kNone = -1;

std::size_t at(std::int64_t i) { return static_cast<std::size_t>(i); }

void requireCapacity(bool ok, const char* what, std::int64_t value) {
  if (!ok) {
    throw Error(std::string("block sparse system: capacity '") + what + "' = " + std::to_string(value) +
                " must be in [0, " + std::to_string(kMaxIndex) + "]");
  }
}

}  // namespace

BlockSparseCapacity BlockSparseCapacity::band(int max_blocks, int band_blocks) {
  const std::int64_t n = std::max(max_blocks, 0);
  const std::int64_t w = std::clamp<std::int64_t>(band_blocks, 0, std::max<std::int64_t>(n - 1, 0));
  // Block column j holds min(j, w) blocks above the diagonal: n·w − w(w+1)/2 in all. L's column j holds as
  // many below the diagonal, so the factor's off-diagonal count is the same.
  const std::int64_t off_diagonal = n * w - w * (w + 1) / 2;
  BlockSparseCapacity capacity;
  capacity.max_blocks = static_cast<int>(n);
  capacity.max_pattern_blocks = n + off_diagonal;
  capacity.max_factor_nonzeros = factorNonzeros(n, off_diagonal);
  return capacity;
}

BlockSparseSystem::BlockSparseSystem(const BlockSparseCapacity& capacity) : capacity_(capacity) {
  const std::int64_t n = capacity.max_blocks;
  requireCapacity(n >= 0, "max_blocks", n);
  requireCapacity(capacity.max_pattern_blocks >= 0 && capacity.max_pattern_blocks <= kMaxIndex, "max_pattern_blocks",
                  capacity.max_pattern_blocks);
  requireCapacity(capacity.max_factor_nonzeros >= 0, "max_factor_nonzeros", capacity.max_factor_nonzeros);
  const std::int64_t factor_blocks =
      std::max<std::int64_t>(capacity.max_factor_nonzeros - BlockSparseCapacity::factorNonzeros(n, 0), 0) /
      BlockSparseCapacity::kBlockNonzeros;
  requireCapacity(factor_blocks <= kMaxIndex, "max_factor_nonzeros / 144", factor_blocks);
  max_factor_blocks_ = static_cast<int>(factor_blocks);

  const std::size_t p = at(capacity.max_pattern_blocks);
  list_head_.resize(at(n));
  list_next_.resize(p);
  list_row_.resize(p);
  column_begin_.resize(at(n) + 1);
  pattern_row_.resize(p);
  // The blocks are written first at the first closure, and the factor's further as the graph grows:
  // resident now, so RSS does not grow (or fault) mid-run (resident_memory.hpp).
  resizeResident(blocks_, p, Matrix12d::Zero().eval());
  resizeResident(gradient_, at(n), Vector12d::Zero().eval());
  parent_.resize(at(n));
  flag_.resize(at(n));
  reach_.resize(at(n));
  path_.resize(at(n));
  factor_begin_.resize(at(n) + 1);
  factor_fill_.resize(at(n));
  factor_row_.resize(at(factor_blocks));
  resizeResident(factor_off_, at(factor_blocks), Matrix12d::Zero().eval());
  resizeResident(factor_diag_, at(n), Matrix12d::Zero().eval());
  resizeResident(work_, at(n), Matrix12d::Zero().eval());
}

std::int64_t BlockSparseSystem::factorNonzeros() const {
  return valid_ ? BlockSparseCapacity::factorNonzeros(block_count_, factor_blocks_) : 0;
}

bool BlockSparseSystem::insertPair(int i, int j) {
  for (int e = list_head_[at(j)]; e != kNone; e = list_next_[at(e)]) {
    if (list_row_[at(e)] == i) return true;
  }
  if (pattern_blocks_ >= capacity_.max_pattern_blocks) return false;
  const int e = pattern_blocks_++;
  list_row_[at(e)] = i;
  list_next_[at(e)] = list_head_[at(j)];
  list_head_[at(j)] = e;
  return true;
}

bool BlockSparseSystem::setPattern(int block_count, std::span<const std::pair<int, int>> pairs) {
  valid_ = false;
  block_count_ = 0;
  pattern_blocks_ = 0;
  factor_blocks_ = 0;
  if (block_count < 0 || block_count > capacity_.max_blocks) return false;
  const auto fail = [this] {
    pattern_blocks_ = 0;
    block_count_ = 0;
    return false;
  };

  // Deduplicate into one linked list per block column (scratch arrays sized by the capacity): a lookup walks
  // the column's blocks, about 2·band for the graph's patterns.
  std::fill_n(list_head_.begin(), block_count, kNone);
  for (int i = 0; i < block_count; ++i) {
    if (!insertPair(i, i)) return fail();
  }
  for (const auto& [a, b] : pairs) {
    if (a < 0 || b < 0 || a >= block_count || b >= block_count) return fail();
    if (!insertPair(std::min(a, b), std::max(a, b))) return fail();
  }

  // Compressed block columns, rows ascending: the diagonal block ends its column.
  int next = 0;
  for (int j = 0; j < block_count; ++j) {
    column_begin_[at(j)] = next;
    for (int e = list_head_[at(j)]; e != kNone; e = list_next_[at(e)]) pattern_row_[at(next++)] = list_row_[at(e)];
    std::sort(pattern_row_.begin() + column_begin_[at(j)], pattern_row_.begin() + next);
  }
  column_begin_[at(block_count)] = next;

  block_count_ = block_count;
  if (!analyse()) return fail();
  valid_ = true;
  setZero();
  return true;
}

bool BlockSparseSystem::analyse() {
  const int n = block_count_;
  // Elimination tree (Liu's algorithm with path compression; flag_ holds the compressed ancestors): for
  // every H_ik ≠ 0, i < k, k is an ancestor of i; the parent of i is the first such k met going up.
  std::vector<int>& ancestor = flag_;
  for (int k = 0; k < n; ++k) {
    parent_[at(k)] = kNone;
    ancestor[at(k)] = kNone;
    for (int p = column_begin_[at(k)]; p < column_begin_[at(k) + 1] - 1; ++p) {
      for (int i = pattern_row_[at(p)]; i != kNone && i < k;) {
        const int up = ancestor[at(i)];
        ancestor[at(i)] = k;
        if (up == kNone) parent_[at(i)] = k;
        i = up;
      }
    }
  }
  // Column counts of L: row k of L is the union of the tree paths from every i with H_ik ≠ 0 up to k, so
  // walking them (marking visited nodes with k) counts each L(k, j) once. O(blocks of L). Every path ends
  // at k (marked first): k is an ancestor of every such i by construction of the tree.
  std::int64_t total = 0;
  for (int k = 0; k < n; ++k) factor_fill_[at(k)] = 0;
  for (int k = 0; k < n; ++k) {
    flag_[at(k)] = k;
    for (int p = column_begin_[at(k)]; p < column_begin_[at(k) + 1] - 1; ++p) {
      for (int i = pattern_row_[at(p)]; flag_[at(i)] != k; i = parent_[at(i)]) {
        ++factor_fill_[at(i)];
        flag_[at(i)] = k;
        if (++total > max_factor_blocks_) return false;
      }
    }
  }
  if (BlockSparseCapacity::factorNonzeros(n, total) > capacity_.max_factor_nonzeros) return false;
  factor_blocks_ = static_cast<int>(total);
  factor_begin_[0] = 0;
  for (int j = 0; j < n; ++j) factor_begin_[at(j) + 1] = factor_begin_[at(j)] + factor_fill_[at(j)];
  return true;
}

int BlockSparseSystem::blockIndex(int i, int j) const {
  const auto first = pattern_row_.begin() + column_begin_[at(j)];
  const auto last = pattern_row_.begin() + column_begin_[at(j) + 1];
  const auto it = std::lower_bound(first, last, i);
  assert(it != last && *it == i && "block pair not in the pattern");
  return static_cast<int>(it - pattern_row_.begin());
}

void BlockSparseSystem::setZero() {
  for (int b = 0; b < pattern_blocks_; ++b) blocks_[at(b)].setZero();
  for (int i = 0; i < block_count_; ++i) gradient_[at(i)].setZero();
}

void BlockSparseSystem::addBlock(int i, int j, const Matrix12d& H_block) {
  if (!valid_) return;
  if (i <= j) {
    blocks_[at(blockIndex(i, j))] += H_block;
  } else {
    blocks_[at(blockIndex(j, i))] += H_block.transpose();
  }
}

void BlockSparseSystem::addGradient(int i, const Vector12d& b_block) {
  if (!valid_) return;
  gradient_[at(i)] += b_block;
}

int BlockSparseSystem::rowReach(int k) {
  // Each path from an i with H_ik ≠ 0 up to the first marked node is pushed in reverse, so that reach_ from
  // `top` on lists descendants before ancestors: the order the triangular solve needs.
  int top = block_count_;
  flag_[at(k)] = k;
  for (int p = column_begin_[at(k)]; p < column_begin_[at(k) + 1] - 1; ++p) {
    int length = 0;
    for (int i = pattern_row_[at(p)]; flag_[at(i)] != k; i = parent_[at(i)]) {
      path_[at(length++)] = i;
      flag_[at(i)] = k;
    }
    while (length > 0) reach_[at(--top)] = path_[at(--length)];
  }
  return top;
}

bool BlockSparseSystem::factorize(double damping, double lambda) {
  const int n = block_count_;
  std::fill_n(flag_.begin(), n, kNone);
  std::fill_n(factor_fill_.begin(), n, 0);
  for (int k = 0; k < n; ++k) {
    // Block row k of L D Lᵀ = H: solve L(0:k, 0:k)·W = H(0:k, k) over the reach of row k, where
    // W_j = D_j·L(k, j)ᵀ; then L(k, j) = W_jᵀ·D_j⁻¹ and the diagonal block's Schur complement is
    // S = H_kk − Σ_j L(k, j)·W_j.
    const int top = rowReach(k);
    for (int t = top; t < n; ++t) work_[at(reach_[at(t)])].setZero();
    const int diagonal = column_begin_[at(k) + 1] - 1;
    for (int p = column_begin_[at(k)]; p < diagonal; ++p) work_[at(pattern_row_[at(p)])] = blocks_[at(p)];
    const Matrix12d& H_kk = blocks_[at(diagonal)];
    Matrix12d S = H_kk.selfadjointView<Eigen::Upper>();
    S.diagonal().array() += damping + lambda * H_kk.diagonal().array();

    for (int t = top; t < n; ++t) {
      const int j = reach_[at(t)];
      Matrix12d& W = work_[at(j)];
      const Matrix12d& LD_j = factor_diag_[at(j)];
      LD_j.triangularView<Eigen::UnitLower>().solveInPlace(W);
      // Column j of L holds rows < k so far (rows are appended in order); all of them are in the reach.
      const int slot = factor_begin_[at(j)] + factor_fill_[at(j)]++;
      for (int q = factor_begin_[at(j)]; q < slot; ++q) {
        work_[at(factor_row_[at(q)])].noalias() -= factor_off_[at(q)] * W;
      }
      Matrix12d& L_kj = factor_off_[at(slot)];
      L_kj.noalias() = W.transpose() * LD_j.diagonal().cwiseInverse().asDiagonal();
      factor_row_[at(slot)] = k;
      S.noalias() -= L_kj * W;
    }

    // Dense LDLᵀ of S in place (right-looking): column c's pivot, then the update of the trailing lower part.
    for (int c = 0; c < kB; ++c) {
      const double d = S(c, c);
      if (!(d > 0.0) || !std::isfinite(d)) return false;
      for (int r = c + 1; r < kB; ++r) {
        const double v = S(r, c);  // L(r, c)·d
        S(r, c) = v / d;
        for (int m = c + 1; m <= r; ++m) S(r, m) -= v * S(m, c);  // S(m, c) is already L(m, c) for m < r
      }
    }
    factor_diag_[at(k)] = S;
  }
  return true;
}

bool BlockSparseSystem::solve(double damping, double lambda, Eigen::Ref<Eigen::VectorXd> delta) {
  if (!valid_ || delta.size() != static_cast<Eigen::Index>(kB) * block_count_) return false;
  if (!factorize(damping, lambda)) return false;
  const int n = block_count_;
  const auto z = [&](int j) { return delta.segment<kB>(static_cast<Eigen::Index>(kB) * j); };
  // L·y = −b (forward, column by column), then D·w = y, then Lᵀ·δ = w (backward, row by row of Lᵀ).
  for (int j = 0; j < n; ++j) z(j) = -gradient_[at(j)];
  for (int j = 0; j < n; ++j) {
    const Matrix12d& LD_j = factor_diag_[at(j)];
    Vector12d y = z(j);
    LD_j.triangularView<Eigen::UnitLower>().solveInPlace(y);
    for (int q = factor_begin_[at(j)]; q < factor_begin_[at(j) + 1]; ++q) {
      z(factor_row_[at(q)]).noalias() -= factor_off_[at(q)] * y;
    }
    z(j) = y.cwiseQuotient(LD_j.diagonal());
  }
  for (int j = n - 1; j >= 0; --j) {
    Vector12d w = z(j);
    for (int q = factor_begin_[at(j)]; q < factor_begin_[at(j) + 1]; ++q) {
      w.noalias() -= factor_off_[at(q)].transpose() * z(factor_row_[at(q)]);
    }
    factor_diag_[at(j)].triangularView<Eigen::UnitLower>().transpose().solveInPlace(w);
    z(j) = w;
  }
  return delta.allFinite();
}

}  // namespace vifusion::loop
