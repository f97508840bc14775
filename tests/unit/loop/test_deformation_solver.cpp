// The deformation graph's block-sparse LDLᵀ solver: δ against a dense Eigen solve on random positive
// definite systems with the graph's banded pattern and long-range pairs, damping and λ, zero heap
// allocations after construction, capacity overflow and non-positive-definite systems failing cleanly, and
// the graph's capacity from its options.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "vifusion/core/error.hpp"
#include "vifusion/loop/deformation_graph.hpp"
#include "vifusion/loop/deformation_solver.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::loop {
namespace {

constexpr int kB = kNodeParamDim;
/// δ against the dense solve, relative ‖δ − δ_dense‖/‖δ_dense‖: both are backward stable on matrices with
/// condition numbers around 1e3 (priors ≥ 0.1·I, terms O(1…10)), so 1e-9 leaves three orders of margin.
constexpr double kRelativeTolerance = 1e-9;
/// Nodes a term couples: a point bound to kBoundNodes nodes (E_con, E_pin); E_reg couples 2.
constexpr int kTermNodes = kBoundNodes;
using TermJacobian = Eigen::Matrix<double, 3, kB>;

/// A residual of 3 rows on `count` nodes, like the graph's point terms.
struct Term {
  int count = 0;
  std::array<int, kTermNodes> node{};
  std::array<TermJacobian, kTermNodes> J;
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  bool lower_first = false;  ///< add off-diagonal blocks as (larger, smaller): the transposing path
};

/// A random positive definite system: per node a prior 0.1·(AᵀA + I), plus terms on temporal neighbours
/// (E_reg-like), on kTermNodes nodes in a window of consecutive nodes (E_con-like) and on node pairs far apart.
struct Problem {
  int blocks = 0;
  std::vector<std::pair<int, int>> pairs;  ///< every coupled pair, both orders and duplicates on purpose
  std::vector<Matrix12d> prior;
  std::vector<Vector12d> gradient;
  std::vector<Term> terms;
};

struct ProblemShape {
  int blocks = 60;
  int neighbours = 4;     ///< E_reg-like pairs (i, i + 1 … i + neighbours)
  int window = 20;        ///< consecutive nodes a window term draws its kTermNodes nodes from
  int window_terms = 80;  ///< window terms
  int long_range = 3;     ///< pair terms between nodes at least blocks/2 apart
};

Problem makeProblem(const ProblemShape& shape, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const auto random = [&](auto& m) {
    for (Eigen::Index i = 0; i < m.size(); ++i) m.data()[i] = normal(rng);
  };
  const auto uniformInt = [&](int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); };
  Problem p;
  p.blocks = shape.blocks;
  for (int i = 0; i < shape.blocks; ++i) {
    Matrix12d A;
    random(A);
    p.prior.push_back(0.1 * (A.transpose() * A + Matrix12d::Identity()));
    Vector12d g;
    random(g);
    p.gradient.push_back(g);
  }
  const auto addTerm = [&](std::initializer_list<int> nodes) {
    Term t;
    for (const int n : nodes) t.node[static_cast<std::size_t>(t.count++)] = n;
    for (TermJacobian& J : t.J) random(J);
    random(t.r);
    t.lower_first = uniformInt(0, 1) == 1;
    for (int a = 0; a < t.count; ++a) {
      for (int b = a + 1; b < t.count; ++b) {
        const int na = t.node[static_cast<std::size_t>(a)];
        const int nb = t.node[static_cast<std::size_t>(b)];
        p.pairs.emplace_back(t.lower_first ? std::max(na, nb) : na, t.lower_first ? std::min(na, nb) : nb);
      }
    }
    p.terms.push_back(t);
  };
  for (int i = 0; i < shape.blocks; ++i) {
    for (int d = 1; d <= shape.neighbours && i + d < shape.blocks; ++d) addTerm({i, i + d});
  }
  for (int k = 0; k < shape.window_terms; ++k) {
    const int start = uniformInt(0, std::max(shape.blocks - shape.window, 0));
    const int last = std::min(start + shape.window, shape.blocks) - 1;
    addTerm({uniformInt(start, last), uniformInt(start, last), uniformInt(start, last), uniformInt(start, last)});
  }
  for (int k = 0; k < shape.long_range; ++k) {
    const int a = uniformInt(0, shape.blocks / 4);
    addTerm({a, uniformInt(a + shape.blocks / 2, shape.blocks - 1)});
  }
  return p;
}

/// setZero() and every addBlock()/addGradient() of the problem, as the graph's linearize() does.
void load(const Problem& p, BlockSparseSystem& system) {
  system.setZero();
  for (int i = 0; i < p.blocks; ++i) {
    system.addBlock(i, i, p.prior[static_cast<std::size_t>(i)]);
    system.addGradient(i, p.gradient[static_cast<std::size_t>(i)]);
  }
  for (const Term& t : p.terms) {
    for (int a = 0; a < t.count; ++a) {
      const int na = t.node[static_cast<std::size_t>(a)];
      const TermJacobian& J_a = t.J[static_cast<std::size_t>(a)];
      system.addGradient(na, J_a.transpose() * t.r);
      for (int b = 0; b < t.count; ++b) {
        const int nb = t.node[static_cast<std::size_t>(b)];
        const TermJacobian& J_b = t.J[static_cast<std::size_t>(b)];
        if (na < nb) {
          if (t.lower_first) {
            system.addBlock(nb, na, J_b.transpose() * J_a);
          } else {
            system.addBlock(na, nb, J_a.transpose() * J_b);
          }
        } else if (na == nb) {
          system.addBlock(na, nb, J_a.transpose() * J_b);  // both slot orders: symmetric sum
        }
      }
    }
  }
}

Eigen::MatrixXd denseH(const Problem& p) {
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(kB * p.blocks, kB * p.blocks);
  for (int i = 0; i < p.blocks; ++i) H.block<kB, kB>(kB * i, kB * i) += p.prior[static_cast<std::size_t>(i)];
  for (const Term& t : p.terms) {
    for (int a = 0; a < t.count; ++a) {
      for (int b = 0; b < t.count; ++b) {
        H.block<kB, kB>(kB * t.node[static_cast<std::size_t>(a)], kB * t.node[static_cast<std::size_t>(b)]) +=
            t.J[static_cast<std::size_t>(a)].transpose() * t.J[static_cast<std::size_t>(b)];
      }
    }
  }
  return H;
}

Eigen::VectorXd denseB(const Problem& p) {
  Eigen::VectorXd b = Eigen::VectorXd::Zero(kB * p.blocks);
  for (int i = 0; i < p.blocks; ++i) b.segment<kB>(kB * i) += p.gradient[static_cast<std::size_t>(i)];
  for (const Term& t : p.terms) {
    for (int a = 0; a < t.count; ++a) {
      b.segment<kB>(kB * t.node[static_cast<std::size_t>(a)]) += t.J[static_cast<std::size_t>(a)].transpose() * t.r;
    }
  }
  return b;
}

/// Room for any pattern on `blocks` nodes: the dense upper triangle and its dense factor.
BlockSparseCapacity denseCapacity(int blocks) {
  const std::int64_t n = blocks;
  return {blocks, n * (n + 1) / 2, BlockSparseCapacity::factorNonzeros(n, n * (n - 1) / 2)};
}

double relativeError(const Eigen::VectorXd& x, const Eigen::VectorXd& reference) {
  return (x - reference).norm() / reference.norm();
}

TEST(BlockSparseSystem, MatchesDenseSolveOnBandedPatternsWithLongRangePairs) {
  const std::array<ProblemShape, 4> shapes = {{
      {60, 4, 20, 80, 3},    // the loop closure's band, a few long-range pairs
      {120, 2, 20, 200, 6},  // ElasticFusion's 2 neighbours per side
      {40, 1, 5, 30, 0},     // narrow band, no long-range pairs
      {8, 4, 20, 10, 1},     // window wider than the graph
  }};
  unsigned seed = 1;
  for (const ProblemShape& shape : shapes) {
    SCOPED_TRACE(shape.blocks);
    const Problem p = makeProblem(shape, seed++);
    BlockSparseSystem system(denseCapacity(shape.blocks));
    ASSERT_TRUE(system.setPattern(p.blocks, p.pairs));
    EXPECT_EQ(system.blockCount(), p.blocks);
    load(p, system);
    Eigen::VectorXd delta(kB * p.blocks);
    ASSERT_TRUE(system.solve(0.0, 0.0, delta));
    const Eigen::VectorXd reference = denseH(p).ldlt().solve(-denseB(p));
    EXPECT_LT(relativeError(delta, reference), kRelativeTolerance);
  }
}

TEST(BlockSparseSystem, PatternIsDeduplicatedAndBandCapacityIsExact) {
  BlockSparseSystem system(denseCapacity(4));
  const std::vector<std::pair<int, int>> pairs = {{0, 1}, {1, 0}, {0, 1}, {2, 2}, {3, 1}};
  ASSERT_TRUE(system.setPattern(4, pairs));
  EXPECT_EQ(system.patternBlocks(), 4 + 2);  // diagonal, (0, 1), (1, 3)

  // A full band of width 3 on 10 blocks: 10 + 3·10 − 6 = 34 blocks, and L fills exactly the band.
  constexpr int kBlocks = 10;
  constexpr int kBand = 3;
  const BlockSparseCapacity band = BlockSparseCapacity::band(kBlocks, kBand);
  EXPECT_EQ(band.max_pattern_blocks, 34);
  EXPECT_EQ(band.max_factor_nonzeros, BlockSparseCapacity::factorNonzeros(kBlocks, 24));
  std::vector<std::pair<int, int>> full;
  for (int i = 0; i < kBlocks; ++i) {
    for (int j = i + 1; j <= i + kBand && j < kBlocks; ++j) full.emplace_back(j, i);
  }
  BlockSparseSystem banded(band);
  ASSERT_TRUE(banded.setPattern(kBlocks, full));
  EXPECT_EQ(banded.patternBlocks(), 34);
  EXPECT_EQ(banded.factorNonzeros(), band.max_factor_nonzeros);
  // Band of the whole graph: a dense matrix.
  EXPECT_EQ(BlockSparseCapacity::band(4, 10).max_pattern_blocks, 10);
}

TEST(BlockSparseSystem, DampingAndLambdaScaleTheDiagonalAsDocumented) {
  const Problem p = makeProblem({50, 4, 20, 60, 2}, 11);
  BlockSparseSystem system(denseCapacity(p.blocks));
  ASSERT_TRUE(system.setPattern(p.blocks, p.pairs));
  load(p, system);
  const Eigen::MatrixXd H = denseH(p);
  const Eigen::VectorXd b = denseB(p);
  Eigen::VectorXd delta(kB * p.blocks);
  // Several solves on one set of blocks: H itself is never modified.
  for (const auto& [damping, lambda] :
       {std::pair{0.5, 0.0}, std::pair{0.0, 0.3}, std::pair{2.0, 10.0}, std::pair{1e-9, 0.0}}) {
    SCOPED_TRACE(lambda);
    ASSERT_TRUE(system.solve(damping, lambda, delta));
    Eigen::MatrixXd A = H;
    A.diagonal() += lambda * H.diagonal() + Eigen::VectorXd::Constant(H.rows(), damping);
    EXPECT_LT(relativeError(delta, A.llt().solve(-b)), kRelativeTolerance);
  }
}

TEST(BlockSparseSystem, SetPatternAndSolveAllocateNothingAfterConstruction) {
  // Start-up: the system for 120 nodes and the test's problems (their vectors allocate).
  const std::array<Problem, 3> problems = {makeProblem({120, 4, 20, 150, 2}, 21), makeProblem({80, 2, 20, 100, 0}, 22),
                                           makeProblem({120, 4, 20, 200, 4}, 23)};
  BlockSparseSystem system(denseCapacity(120));
  Eigen::VectorXd delta(kB * 120);
  std::array<double, 3> norms{};

  const std::uint64_t before = test::heapAllocationCount();
  for (std::size_t k = 0; k < problems.size(); ++k) {
    const Problem& p = problems[k];
    const bool pattern = system.setPattern(p.blocks, p.pairs);
    load(p, system);
    auto head = delta.head(kB * p.blocks);
    const bool solved = system.solve(0.0, 0.0, head) && system.solve(1e-9, 1e-3, head);
    norms[k] = pattern && solved ? head.norm() : 0.0;
  }
  const std::uint64_t after = test::heapAllocationCount();
  EXPECT_EQ(after, before);
  for (const double norm : norms) EXPECT_GT(norm, 0.0);  // every pattern fitted and every solve succeeded
  const std::vector<int> probe(3);                       // the counter does see allocations
  EXPECT_GT(test::heapAllocationCount(), after);
}

TEST(BlockSparseSystem, PatternBeyondCapacityFailsCleanly) {
  constexpr int kBlocks = 30;
  constexpr int kBand = 2;
  std::vector<std::pair<int, int>> band_pairs;  // the full band: L fills the factor capacity exactly
  for (int i = 0; i < kBlocks; ++i) {
    for (int j = i + 1; j <= i + kBand && j < kBlocks; ++j) band_pairs.emplace_back(i, j);
  }
  constexpr int kSpareBlocks = 10;  // pattern room beyond the band: the factor is what overflows below
  BlockSparseCapacity capacity = BlockSparseCapacity::band(kBlocks, kBand);
  capacity.max_pattern_blocks += kSpareBlocks;
  BlockSparseSystem system(capacity);
  Eigen::VectorXd delta(kB * kBlocks);

  // A long-range pair fills row 29 of L back to column 0: beyond the band's factor, though the pattern fits.
  std::vector<std::pair<int, int>> far = band_pairs;
  far.emplace_back(0, kBlocks - 1);
  EXPECT_FALSE(system.setPattern(kBlocks, far));
  EXPECT_EQ(system.blockCount(), 0);
  EXPECT_EQ(system.factorNonzeros(), 0);
  system.setZero();
  system.addBlock(0, kBlocks - 1, Matrix12d::Identity());  // ignored without a pattern
  system.addGradient(3, Vector12d::Ones());
  EXPECT_FALSE(system.solve(1.0, 0.0, delta));

  // Too many distinct blocks (27 more), too many nodes, a node out of range.
  std::vector<std::pair<int, int>> wide = band_pairs;
  for (int i = 0; i + 3 < kBlocks; ++i) wide.emplace_back(i, i + 3);
  EXPECT_FALSE(system.setPattern(kBlocks, wide));
  EXPECT_FALSE(system.setPattern(kBlocks + 1, {}));
  const std::vector<std::pair<int, int>> outside = {{0, kBlocks}};
  EXPECT_FALSE(system.setPattern(kBlocks, outside));
  const std::vector<std::pair<int, int>> negative = {{-1, 2}};
  EXPECT_FALSE(system.setPattern(kBlocks, negative));

  // The system is usable again with a pattern that fits.
  ASSERT_TRUE(system.setPattern(kBlocks, band_pairs));
  for (int i = 0; i < kBlocks; ++i) {
    system.addBlock(i, i, Matrix12d::Identity());
    system.addGradient(i, Vector12d::Ones());
  }
  ASSERT_TRUE(system.solve(0.0, 0.0, delta));
  EXPECT_NEAR(delta.maxCoeff(), -1.0, 1e-15);
  EXPECT_NEAR(delta.minCoeff(), -1.0, 1e-15);

  // Capacity 0 (default-constructed) takes the empty system only.
  BlockSparseSystem empty;
  EXPECT_FALSE(empty.setPattern(1, {}));
  EXPECT_TRUE(empty.setPattern(0, {}));
}

TEST(BlockSparseSystem, NotPositiveDefiniteReturnsFalse) {
  const Problem p = makeProblem({20, 2, 8, 20, 0}, 31);
  BlockSparseSystem system(denseCapacity(p.blocks));
  ASSERT_TRUE(system.setPattern(p.blocks, p.pairs));
  Eigen::VectorXd delta(kB * p.blocks);

  // A node without any term: a zero block row, pivot exactly 0 without damping; damping makes it definite.
  system.setZero();
  for (int i = 1; i < p.blocks; ++i) system.addBlock(i, i, p.prior[static_cast<std::size_t>(i)]);
  EXPECT_FALSE(system.solve(0.0, 0.0, delta));
  EXPECT_FALSE(system.solve(0.0, 0.5, delta));  // λ·diag(H) of a zero diagonal is zero too
  EXPECT_TRUE(system.solve(1e-6, 0.0, delta));

  // Indefinite: a negative eigenvalue in a later node's block, reached only after elimination.
  load(p, system);
  Matrix12d negative = Matrix12d::Zero();
  negative(5, 5) = -1e3;
  system.addBlock(p.blocks - 1, p.blocks - 1, negative);
  EXPECT_FALSE(system.solve(1e-9, 0.0, delta));

  // Positive semi-definite but singular: two equal nodes coupled, J = [I, −I]: H = [[I, −I], [−I, I]].
  BlockSparseSystem pair(denseCapacity(2));
  const std::vector<std::pair<int, int>> coupled = {{0, 1}};
  ASSERT_TRUE(pair.setPattern(2, coupled));
  pair.addBlock(0, 0, Matrix12d::Identity());
  pair.addBlock(1, 1, Matrix12d::Identity());
  pair.addBlock(0, 1, -Matrix12d::Identity());
  Eigen::VectorXd pair_delta(2 * kB);
  EXPECT_FALSE(pair.solve(0.0, 0.0, pair_delta));
  EXPECT_TRUE(pair.solve(1e-9, 0.0, pair_delta));

  // Not finite.
  load(p, system);
  Matrix12d nan = Matrix12d::Zero();
  nan(2, 7) = std::numeric_limits<double>::quiet_NaN();
  system.addBlock(3, 3, nan);
  EXPECT_FALSE(system.solve(1e-9, 0.0, delta));

  // Wrong delta size.
  load(p, system);
  Eigen::VectorXd short_delta(kB * p.blocks - 1);
  EXPECT_FALSE(system.solve(1e-9, 0.0, short_delta));
  EXPECT_TRUE(system.solve(1e-9, 0.0, delta));
}

TEST(BlockSparseSystem, RejectsNegativeCapacities) {
  EXPECT_THROW(BlockSparseSystem(BlockSparseCapacity{-1, 0, 0}), Error);
  EXPECT_THROW(BlockSparseSystem(BlockSparseCapacity{1, -1, 0}), Error);
  EXPECT_THROW(BlockSparseSystem(BlockSparseCapacity{1, 1, -1}), Error);
}

/// A graph on a strip around a cylinder (radius 2 m, two heights), one node per frame: the loop's start and
/// end (frames 0 and 199) meet in space and are far apart in time.
std::vector<NodeSample> cylinderSamples(int count) {
  std::vector<NodeSample> samples;
  for (int i = 0; i < count; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / count;
    samples.push_back(
        {Eigen::Vector3d(2.0 * std::cos(angle), 2.0 * std::sin(angle), 0.3 * (i % 2)), static_cast<std::uint32_t>(i)});
  }
  return samples;
}

TEST(DeformationGraphSolver, CapacityFromOptionsHoldsTheBandAndOneFarRelativeConstraint) {
  constexpr int kNodes = 200;
  DeformationGraphOptions options;
  options.max_nodes = kNodes;
  options.neighbours_per_side = 4;
  const std::vector<NodeSample> samples = cylinderSamples(kNodes);
  DeformationGraph graph(options);
  graph.build(samples);
  ASSERT_EQ(graph.nodeCount(), kNodes);
  const Eigen::Vector3d shift(0.01, 0.0, 0.0);
  for (int i = 0; i < kNodes; i += 3) {
    const NodeSample& s = samples[static_cast<std::size_t>(i)];
    if (i < kNodes / 2) {
      graph.addPin(s.p_W, s.time);
    } else {
      graph.addConstraint(s.p_W, s.time, s.p_W + shift);
    }
  }
  // The loop: frame 2's and frame 197's surfaces should coincide.
  graph.addRelative(samples[2].p_W, 2, samples[197].p_W, 197);
  DeformationSolveResult result = graph.solve();
  EXPECT_TRUE(result.hasSolution()) << deformationSolveStatusName(result.status);
  graph.revert();

  // Later solves on the same pattern allocate nothing (the pattern's pair list was built by the first).
  const std::uint64_t before = test::heapAllocationCount();
  result = graph.solve();
  EXPECT_EQ(test::heapAllocationCount(), before);
  EXPECT_TRUE(result.hasSolution());
  graph.revert();

  // Relative constraints from every later window back to the first: beyond the reserve, reported as a
  // numerical failure without a pending set.
  for (int t = kNodes / 2; t < kNodes; t += 5) {
    graph.addRelative(samples[1].p_W, 1, samples[static_cast<std::size_t>(t)].p_W, static_cast<std::uint32_t>(t));
  }
  result = graph.solve();
  EXPECT_EQ(result.status, DeformationSolveStatus::kNumericalFailure);
  EXPECT_FALSE(graph.hasPending());
}

}  // namespace
}  // namespace vifusion::loop
