#include "vifusion/loop/deformation_solver.hpp"

#include <algorithm>
#include <cassert>

namespace vifusion::loop {

void BlockSparseSystem::setPattern(int block_count, std::span<const std::pair<int, int>> pairs) {
  constexpr int kB = kNodeParamDim;
  block_count_ = block_count;
  pairs_.clear();
  pairs_.reserve(pairs.size() + static_cast<std::size_t>(block_count));
  for (int i = 0; i < block_count; ++i) pairs_.emplace_back(i, i);
  for (const auto& [a, b] : pairs) pairs_.emplace_back(std::min(a, b), std::max(a, b));
  // Column-major block order: by column j, then row i, so each block column is contiguous.
  std::sort(pairs_.begin(), pairs_.end(), [](const auto& p, const auto& q) {
    return p.second != q.second ? p.second < q.second : p.first < q.first;
  });
  pairs_.erase(std::unique(pairs_.begin(), pairs_.end()), pairs_.end());

  column_begin_.assign(static_cast<std::size_t>(block_count) + 1, 0);
  for (const auto& p : pairs_) ++column_begin_[static_cast<std::size_t>(p.second) + 1];
  for (int j = 0; j < block_count; ++j) {
    column_begin_[static_cast<std::size_t>(j) + 1] += column_begin_[static_cast<std::size_t>(j)];
  }

  // Compressed-column upper triangle: scalar column 12j + c holds, for each block (i, j) of block column j
  // in row order, the rows 12i … 12i + 11, except the diagonal block, which holds rows 12j … 12j + c.
  const int n = kB * block_count;
  std::vector<int> outer(static_cast<std::size_t>(n) + 1, 0);
  std::vector<int> inner;
  value_offset_.assign(pairs_.size() * kB, 0);
  for (int j = 0; j < block_count; ++j) {
    for (int c = 0; c < kB; ++c) {
      const int col = kB * j + c;
      outer[static_cast<std::size_t>(col)] = static_cast<int>(inner.size());
      for (int b = column_begin_[static_cast<std::size_t>(j)]; b < column_begin_[static_cast<std::size_t>(j) + 1];
           ++b) {
        const int i = pairs_[static_cast<std::size_t>(b)].first;
        value_offset_[static_cast<std::size_t>(b) * kB + static_cast<std::size_t>(c)] =
            static_cast<std::int64_t>(inner.size());
        const int rows = i == j ? c + 1 : kB;
        for (int r = 0; r < rows; ++r) inner.push_back(kB * i + r);
      }
    }
  }
  outer[static_cast<std::size_t>(n)] = static_cast<int>(inner.size());

  H_.resize(n, n);
  H_.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), H_.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), H_.innerIndexPtr());
  std::fill(H_.valuePtr(), H_.valuePtr() + inner.size(), 0.0);
  blocks_.assign(pairs_.size(), Matrix12d::Zero());
  b_.setZero(n);
  ldlt_.analyzePattern(H_);
  analysed_ = true;
}

int BlockSparseSystem::blockIndex(int i, int j) const {
  const auto first = pairs_.begin() + column_begin_[static_cast<std::size_t>(j)];
  const auto last = pairs_.begin() + column_begin_[static_cast<std::size_t>(j) + 1];
  const auto it = std::lower_bound(first, last, i, [](const std::pair<int, int>& p, int row) { return p.first < row; });
  assert(it != last && it->first == i && "block pair not in the pattern");
  return static_cast<int>(it - pairs_.begin());
}

void BlockSparseSystem::setZero() {
  for (Matrix12d& B : blocks_) B.setZero();
  b_.setZero();
}

void BlockSparseSystem::addBlock(int i, int j, const Matrix12d& H_block) {
  if (i <= j) {
    blocks_[static_cast<std::size_t>(blockIndex(i, j))] += H_block;
  } else {
    blocks_[static_cast<std::size_t>(blockIndex(j, i))] += H_block.transpose();
  }
}

void BlockSparseSystem::addGradient(int i, const Vector12d& b_block) {
  b_.segment<kNodeParamDim>(kNodeParamDim * i) += b_block;
}

bool BlockSparseSystem::solve(double damping, double lambda, Eigen::Ref<Eigen::VectorXd> delta) {
  constexpr int kB = kNodeParamDim;
  if (!analysed_) return false;
  double* values = H_.valuePtr();
  for (std::size_t b = 0; b < pairs_.size(); ++b) {
    const auto [i, j] = pairs_[b];
    Matrix12d& B = blocks_[b];
    for (int c = 0; c < kB; ++c) {
      double* out = values + value_offset_[b * kB + static_cast<std::size_t>(c)];
      const int rows = i == j ? c + 1 : kB;
      for (int r = 0; r < rows; ++r) out[r] = B(r, c);
      if (i == j) out[c] += damping + lambda * B(c, c);
    }
  }
  ldlt_.factorize(H_);
  if (ldlt_.info() != Eigen::Success) return false;
  if (delta.size() != b_.size()) return false;
  delta = ldlt_.solve(-b_);
  return delta.allFinite();
}

}  // namespace vifusion::loop
