#include "vifusion/loop/deformation_graph.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/resident_memory.hpp"

namespace vifusion::loop {
namespace {

constexpr int kMaxNodesLimit = 1'000'000;
constexpr int kMaxNeighboursPerSide = 16;
constexpr int kMaxDampingRetries = 30;  // λ up to 1e-4·10³⁰: far beyond any useful step

void require(bool ok, double value, const char* name, const char* condition) {
  if (!ok || !std::isfinite(value)) {
    throw Error(std::string("deformation graph option '") + name + "' = " + std::to_string(value) +
                " must be finite and " + condition);
  }
}

/// Block rows of L reserved beyond the band for E_rel between windows far apart in time: such a constraint
/// fills the rows of its later window's (at most kBoundNodes) nodes back to the earlier window.
constexpr int kFarFactorRows = kBoundNodes;

/// The normal equations' capacity: every block inside the band of E_reg (neighbours_per_side) and of the
/// binding windows (candidates − 1), which holds E_con, E_pin and E_rel between nearby windows, plus
/// kFarFactorRows rows of L of up to max_nodes − 1 blocks, each coupled to a window of `candidates` nodes.
BlockSparseCapacity solverCapacity(const DeformationGraphOptions& options) {
  const std::int64_t nodes = options.max_nodes;
  BlockSparseCapacity capacity =
      BlockSparseCapacity::band(options.max_nodes, std::max(options.neighbours_per_side, options.candidates - 1));
  capacity.max_pattern_blocks += kFarFactorRows * std::min<std::int64_t>(options.candidates, nodes);
  capacity.max_factor_nonzeros += kFarFactorRows * (nodes - 1) * BlockSparseCapacity::kBlockNonzeros;
  return capacity;
}

template <class V>
std::span<const typename V::value_type> head(const V& v, int count) {
  return {v.data(), static_cast<std::size_t>(count)};
}

}  // namespace

void DeformationGraphOptions::validate() const {
  require(max_nodes >= kBoundNodes + 1 && max_nodes <= kMaxNodesLimit, max_nodes, "max_nodes", "in [5, 1000000]");
  require(sample_stride >= 1, sample_stride, "sample_stride", ">= 1");
  require(neighbours_per_side >= 1 && neighbours_per_side <= kMaxNeighboursPerSide, neighbours_per_side,
          "neighbours_per_side", "in [1, 16]");
  require(candidates >= kBoundNodes + 1, candidates, "candidates", ">= 5");
  require(max_constraints >= 1, max_constraints, "max_constraints", ">= 1");
  require(weight_rot >= 0.0, weight_rot, "weight_rot", ">= 0");
  require(weight_reg >= 0.0, weight_reg, "weight_reg", ">= 0");
  require(weight_con > 0.0, weight_con, "weight_con", "> 0");
  require(weight_imu >= 0.0, weight_imu, "weight_imu", ">= 0");
  require(max_iterations >= 1, max_iterations, "max_iterations", ">= 1");
  require(max_damping_retries >= 0 && max_damping_retries <= kMaxDampingRetries, max_damping_retries,
          "max_damping_retries", "in [0, 30]");
  require(step_tolerance >= 0.0, step_tolerance, "step_tolerance", ">= 0");
  require(relative_cost_tolerance >= 0.0, relative_cost_tolerance, "relative_cost_tolerance", ">= 0");
  require(absolute_cost_tolerance >= 0.0, absolute_cost_tolerance, "absolute_cost_tolerance", ">= 0");
  require(damping >= 0.0, damping, "damping", ">= 0");
}

const char* deformationSolveStatusName(DeformationSolveStatus status) {
  switch (status) {
    case DeformationSolveStatus::kConverged:
      return "converged";
    case DeformationSolveStatus::kMaxIterations:
      return "max_iterations";
    case DeformationSolveStatus::kCostRose:
      return "cost_rose";
    case DeformationSolveStatus::kNumericalFailure:
      return "numerical_failure";
    case DeformationSolveStatus::kNoConstraints:
      return "no_constraints";
  }
  return "unknown";
}

DeformationGraph::DeformationGraph(const DeformationGraphOptions& options) : options_(options) {
  options_.validate();
  const auto nodes = static_cast<std::size_t>(options_.max_nodes);
  // Everything sized here is written first when a graph is built or solved, mid-run: resident now
  // (resident_memory.hpp).
  resizeResident(positions_W_, nodes, Eigen::Vector3d::Zero().eval());
  times_.resize(nodes);
  order_.resize(nodes);
  const std::size_t max_edges = nodes * 2 * static_cast<std::size_t>(options_.neighbours_per_side);
  reserveResident(edges_, max_edges, {});
  reserveResident(constraints_, static_cast<std::size_t>(options_.max_constraints), {});
  const Eigen::Index params = static_cast<Eigen::Index>(kNodeParamDim) * options_.max_nodes;
  committed_.setZero(params);
  pending_.setZero(params);
  iterate_.setZero(params);
  trial_.setZero(params);
  delta_.setZero(params);
  system_ = BlockSparseSystem(solverCapacity(options_));
  // Every edge and, per constraint, each pair among its (at most two) bindings' nodes.
  constexpr std::size_t kPairsPerConstraint = kBoundNodes * (2 * kBoundNodes - 1);
  reserveResident(pattern_pairs_, max_edges + static_cast<std::size_t>(options_.max_constraints) * kPairsPerConstraint,
                  {});
}

void DeformationGraph::build(std::span<const NodeSample> samples, std::uint32_t free_from_time) {
  const auto n = static_cast<std::int64_t>(samples.size());
  const std::int64_t max_nodes = options_.max_nodes;
  const std::int64_t stride = std::max<std::int64_t>(options_.sample_stride, (n + max_nodes - 1) / max_nodes);
  const std::int64_t count = (n + stride - 1) / stride;  // ≤ max_nodes by the choice of stride
  if (count < kBoundNodes + 1) {
    throw Error("deformation graph: " + std::to_string(n) + " samples at stride " + std::to_string(stride) + " give " +
                std::to_string(count) + " nodes; at least 5 are needed");
  }
  node_count_ = 0;
  has_pending_ = false;
  pattern_dirty_ = true;
  constraints_.clear();
  edges_.clear();

  for (std::int64_t k = 0; k < count; ++k) {
    const NodeSample& s = samples[static_cast<std::size_t>(k * stride)];
    if (!s.p_W.allFinite()) {
      throw Error("deformation graph: sample " + std::to_string(k * stride) + " has a non-finite position");
    }
    order_[static_cast<std::size_t>(k)] = static_cast<int>(k * stride);
  }
  // Sort by time, ties by input index: deterministic, and std::sort does not allocate.
  std::sort(order_.begin(), order_.begin() + count, [&](int a, int b) {
    const std::uint32_t ta = samples[static_cast<std::size_t>(a)].time;
    const std::uint32_t tb = samples[static_cast<std::size_t>(b)].time;
    return ta != tb ? ta < tb : a < b;
  });
  node_count_ = static_cast<int>(count);
  for (int i = 0; i < node_count_; ++i) {
    const NodeSample& s = samples[static_cast<std::size_t>(order_[static_cast<std::size_t>(i)])];
    positions_W_[static_cast<std::size_t>(i)] = s.p_W;
    times_[static_cast<std::size_t>(i)] = s.time;
    committed_.segment<kNodeParamDim>(kNodeParamDim * i) = identityNodeParams<double>();
  }
  first_free_node_ =
      static_cast<int>(std::lower_bound(times_.begin(), times_.begin() + node_count_, free_from_time) - times_.begin());
  for (int l = 0; l < node_count_; ++l) {
    for (int n_idx = l - options_.neighbours_per_side; n_idx <= l + options_.neighbours_per_side; ++n_idx) {
      if (n_idx != l && n_idx >= 0 && n_idx < node_count_) edges_.emplace_back(l, n_idx);
    }
  }
}

std::span<const Eigen::Vector3d> DeformationGraph::nodePositions() const { return head(positions_W_, node_count_); }
std::span<const std::uint32_t> DeformationGraph::nodeTimes() const { return head(times_, node_count_); }
std::span<const std::pair<int, int>> DeformationGraph::edges() const { return {edges_.data(), edges_.size()}; }

std::span<const double> DeformationGraph::paramsOf(const Eigen::VectorXd& x) const {
  return {x.data(), static_cast<std::size_t>(kNodeParamDim) * static_cast<std::size_t>(node_count_)};
}

std::span<const double> DeformationGraph::parameters() const { return paramsOf(committed_); }

std::span<const double> DeformationGraph::pendingParameters() const {
  return has_pending_ ? paramsOf(pending_) : std::span<const double>();
}

void DeformationGraph::setGravity(const Eigen::Vector3d& g_W) {
  if (!g_W.allFinite()) throw Error("deformation graph: gravity is not finite");
  g_W_ = g_W;
}

void DeformationGraph::requireBuilt(const char* what) const {
  if (node_count_ == 0) throw Error(std::string("deformation graph: ") + what + " before build()");
}

void DeformationGraph::pushConstraint(const Constraint& c) {
  if (!c.a_W.allFinite() || !c.b_W.allFinite()) throw Error("deformation graph: constraint point is not finite");
  if (static_cast<int>(constraints_.size()) >= options_.max_constraints) {
    throw Error("deformation graph: constraint capacity max_constraints = " + std::to_string(options_.max_constraints) +
                " reached");
  }
  constraints_.push_back(c);
  pattern_dirty_ = true;
}

void DeformationGraph::addConstraint(const Eigen::Vector3d& source_W, std::uint32_t source_time,
                                     const Eigen::Vector3d& target_W) {
  requireBuilt("addConstraint");
  Constraint c;
  c.kind = Kind::kCon;
  c.a_W = source_W;
  c.b_W = target_W;
  c.binding_a = bind(source_W, source_time);
  pushConstraint(c);
}

void DeformationGraph::addPin(const Eigen::Vector3d& p_W, std::uint32_t time) {
  requireBuilt("addPin");
  Constraint c;
  c.kind = Kind::kPin;
  c.a_W = p_W;
  c.b_W = p_W;
  c.binding_a = bind(p_W, time);
  pushConstraint(c);
}

void DeformationGraph::addRelative(const Eigen::Vector3d& a_W, std::uint32_t time_a, const Eigen::Vector3d& b_W,
                                   std::uint32_t time_b) {
  requireBuilt("addRelative");
  Constraint c;
  c.kind = Kind::kRel;
  c.a_W = a_W;
  c.b_W = b_W;
  c.binding_a = bind(a_W, time_a);
  c.binding_b = bind(b_W, time_b);
  pushConstraint(c);
}

void DeformationGraph::clearConstraints() {
  constraints_.clear();
  has_pending_ = false;
  pattern_dirty_ = true;
}

NodeBinding<double> DeformationGraph::bind(const Eigen::Vector3d& p_W, std::uint32_t time) const {
  requireBuilt("bind");
  return bindToNodes<double>(p_W, time, nodePositions(), nodeTimes(), options_.candidates);
}

Eigen::Vector3d DeformationGraph::deformPoint(const Eigen::Vector3d& p_W, std::uint32_t time) const {
  return loop::deformPoint<double>(p_W, bind(p_W, time), nodePositions(), parameters());
}

Eigen::Vector3d DeformationGraph::deformNormal(const Eigen::Vector3d& n_W, const Eigen::Vector3d& p_W,
                                               std::uint32_t time) const {
  return loop::deformNormal<double>(n_W, bind(p_W, time), parameters());
}

SE3d DeformationGraph::deformPose(const SE3d& T_W_C, std::uint32_t time) const {
  return loop::deformPose(T_W_C, bind(T_W_C.translation(), time), nodePositions(), parameters());
}

DeformationTermCosts DeformationGraph::evaluate(std::span<const double> x) const {
  DeformationTermCosts c;
  const auto positions = nodePositions();
  const auto nodeParams = [&](int i) { return NodeParams(Eigen::Map<const NodeParams>(x.data() + kNodeParamDim * i)); };
  const bool imu = options_.use_gravity_term && options_.weight_imu > 0.0;
  for (int i = 0; i < node_count_; ++i) {
    const NodeParams xi = nodeParams(i);
    c.rot += rotResidual(xi).squaredNorm();
    if (imu) c.imu += imuResidual(xi, g_W_).squaredNorm();
  }
  for (const auto& [l, n] : edges_) {
    c.reg += regResidual(positions[static_cast<std::size_t>(l)], nodeParams(l), positions[static_cast<std::size_t>(n)],
                         nodeParams(n))
                 .squaredNorm();
  }
  for (const Constraint& k : constraints_) {
    switch (k.kind) {
      case Kind::kCon:
        c.con += conResidual(k.a_W, k.binding_a, positions, x, k.b_W).squaredNorm();
        break;
      case Kind::kPin:
        c.pin += pinResidual(k.a_W, k.binding_a, positions, x).squaredNorm();
        break;
      case Kind::kRel:
        c.rel += relResidual(k.a_W, k.binding_a, k.b_W, k.binding_b, positions, x).squaredNorm();
        break;
    }
  }
  c.rot *= options_.weight_rot;
  c.reg *= options_.weight_reg;
  c.con *= options_.weight_con;
  c.pin *= options_.weight_con;
  c.rel *= options_.weight_con;
  c.imu *= imu ? options_.weight_imu : 0.0;
  return c;
}

DeformationTermCosts DeformationGraph::cost() const {
  requireBuilt("cost");
  return evaluate(parameters());
}

std::pair<double, double> DeformationGraph::constraintErrors(std::span<const double> x) const {
  double sum = 0.0;
  double max = 0.0;
  int count = 0;
  for (const Constraint& k : constraints_) {
    if (k.kind != Kind::kCon) continue;
    const double e = conResidual(k.a_W, k.binding_a, nodePositions(), x, k.b_W).norm();
    sum += e;
    max = std::max(max, e);
    ++count;
  }
  return {count > 0 ? sum / count : 0.0, max};
}

bool DeformationGraph::buildPattern() {
  pattern_pairs_.assign(edges_.begin(), edges_.end());  // within the capacity reserved at construction
  for (const Constraint& k : constraints_) {
    std::array<int, 2 * kBoundNodes> nodes{};
    int count = 0;
    for (const int i : k.binding_a.node) nodes[static_cast<std::size_t>(count++)] = i;
    if (k.kind == Kind::kRel) {
      for (const int i : k.binding_b.node) nodes[static_cast<std::size_t>(count++)] = i;
    }
    for (int a = 0; a < count; ++a) {
      for (int b = a + 1; b < count; ++b) {
        pattern_pairs_.emplace_back(nodes[static_cast<std::size_t>(a)], nodes[static_cast<std::size_t>(b)]);
      }
    }
  }
  pattern_dirty_ = !system_.setPattern(node_count_, pattern_pairs_);  // false: beyond the solver's capacity
  return !pattern_dirty_;
}

void DeformationGraph::addPointTerm(const NodeBinding<double>* bindings, const PointJacobians* J, int count,
                                    const Eigen::Vector3d& r, double weight) {
  // Ordered slot pairs (a, b) with node(a) ≤ node(b) add J_aᵀJ_b to block (node(a), node(b)): each
  // off-diagonal block once, and slots sharing a node contribute both J_aᵀJ_b and J_bᵀJ_a to its diagonal.
  for (int sa = 0; sa < count * kBoundNodes; ++sa) {
    const int ba = sa / kBoundNodes;
    const auto ka = static_cast<std::size_t>(sa % kBoundNodes);
    const int na = bindings[ba].node[ka];
    const NodeJacobian& Ja = J[ba][ka];
    addGradient(na, weight * Ja.transpose() * r);
    for (int sb = 0; sb < count * kBoundNodes; ++sb) {
      const int bb = sb / kBoundNodes;
      const auto kb = static_cast<std::size_t>(sb % kBoundNodes);
      const int nb = bindings[bb].node[kb];
      if (na > nb) continue;
      addBlock(na, nb, weight * Ja.transpose() * J[bb][kb]);
    }
  }
}

void DeformationGraph::addBlock(int i, int j, const Matrix12d& H_block) {
  if (i >= first_free_node_ && j >= first_free_node_) system_.addBlock(i, j, H_block);
}

void DeformationGraph::addGradient(int i, const Vector12d& b_block) {
  if (i >= first_free_node_) system_.addGradient(i, b_block);
}

void DeformationGraph::linearize(std::span<const double> x) {
  system_.setZero();
  // A held node's row is I·δ = 0: its parameters are constants to every term that touches it.
  for (int i = 0; i < first_free_node_; ++i) system_.addBlock(i, i, Matrix12d::Identity());
  const auto positions = nodePositions();
  const auto nodeParams = [&](int i) { return NodeParams(Eigen::Map<const NodeParams>(x.data() + kNodeParamDim * i)); };
  const bool imu = options_.use_gravity_term && options_.weight_imu > 0.0;
  for (int i = first_free_node_; i < node_count_; ++i) {
    const NodeParams xi = nodeParams(i);
    RotJacobian J_rot;
    const RotResidual r_rot = rotResidual(xi, &J_rot);
    Matrix12d H = options_.weight_rot * J_rot.transpose() * J_rot;
    Vector12d b = options_.weight_rot * J_rot.transpose() * r_rot;
    if (imu) {
      NodeJacobian J_imu;
      const Eigen::Vector3d r_imu = imuResidual(xi, g_W_, &J_imu);
      H += options_.weight_imu * J_imu.transpose() * J_imu;
      b += options_.weight_imu * J_imu.transpose() * r_imu;
    }
    addBlock(i, i, H);
    addGradient(i, b);
  }
  const double w_reg = options_.weight_reg;
  for (const auto& [l, n] : edges_) {
    NodeJacobian J_l;
    NodeJacobian J_n;
    const Eigen::Vector3d r = regResidual(positions[static_cast<std::size_t>(l)], nodeParams(l),
                                          positions[static_cast<std::size_t>(n)], nodeParams(n), &J_l, &J_n);
    addBlock(l, l, w_reg * J_l.transpose() * J_l);
    addBlock(n, n, w_reg * J_n.transpose() * J_n);
    addBlock(l, n, w_reg * J_l.transpose() * J_n);
    addGradient(l, w_reg * J_l.transpose() * r);
    addGradient(n, w_reg * J_n.transpose() * r);
  }
  const double w_con = options_.weight_con;
  for (const Constraint& k : constraints_) {
    std::array<PointJacobians, 2> J;
    const std::array<NodeBinding<double>, 2> bindings = {k.binding_a, k.binding_b};
    switch (k.kind) {
      case Kind::kCon:
        addPointTerm(bindings.data(), J.data(), 1, conResidual(k.a_W, k.binding_a, positions, x, k.b_W, &J[0]), w_con);
        break;
      case Kind::kPin:
        addPointTerm(bindings.data(), J.data(), 1, pinResidual(k.a_W, k.binding_a, positions, x, &J[0]), w_con);
        break;
      case Kind::kRel:
        addPointTerm(bindings.data(), J.data(), 2,
                     relResidual(k.a_W, k.binding_a, k.b_W, k.binding_b, positions, x, &J[0], &J[1]), w_con);
        break;
    }
  }
}

DeformationSolveResult DeformationGraph::solve() {
  requireBuilt("solve");
  has_pending_ = false;
  DeformationSolveResult result;
  const Eigen::Index dim = static_cast<Eigen::Index>(kNodeParamDim) * node_count_;
  iterate_.head(dim) = committed_.head(dim);
  result.initial_cost = evaluate(paramsOf(iterate_));
  result.final_cost = result.initial_cost;
  std::tie(result.mean_constraint_error_before_m, result.max_constraint_error_before_m) =
      constraintErrors(paramsOf(iterate_));
  result.mean_constraint_error_after_m = result.mean_constraint_error_before_m;
  result.max_constraint_error_after_m = result.max_constraint_error_before_m;
  if (constraints_.empty()) {
    result.status = DeformationSolveStatus::kNoConstraints;
    return result;
  }
  double cost = result.initial_cost.total();
  if (!std::isfinite(cost)) {
    result.status = DeformationSolveStatus::kNumericalFailure;
    return result;
  }
  if (pattern_dirty_ && !buildPattern()) {
    result.status = DeformationSolveStatus::kNumericalFailure;
    return result;
  }

  result.status = DeformationSolveStatus::kMaxIterations;
  // Marquardt factor: 0 is plain Gauss-Newton (ElasticFusion). A rising step is retried on the same
  // linearisation with a growing λ; a step accepted without retries lets λ shrink back towards 0.
  constexpr double kFirstLambda = 1e-4;
  double lambda = 0.0;
  for (int it = 0; it < options_.max_iterations && result.status == DeformationSolveStatus::kMaxIterations; ++it) {
    if (cost <= options_.absolute_cost_tolerance) {
      result.status = DeformationSolveStatus::kConverged;
      break;
    }
    linearize(paramsOf(iterate_));
    for (int attempt = 0;; ++attempt) {
      if (!system_.solve(options_.damping, lambda, delta_.head(dim))) {
        result.status = DeformationSolveStatus::kNumericalFailure;
        return result;
      }
      trial_.head(dim) = iterate_.head(dim) + delta_.head(dim);
      const DeformationTermCosts trial_cost = evaluate(paramsOf(trial_));
      const double new_cost = trial_cost.total();
      if (!std::isfinite(new_cost)) {
        result.status = DeformationSolveStatus::kNumericalFailure;
        return result;
      }
      if (new_cost < cost) {
        iterate_.head(dim) = trial_.head(dim);
        result.final_cost = trial_cost;
        ++result.iterations;
        const double relative_decrease = (cost - new_cost) / cost;
        cost = new_cost;
        if (attempt == 0) lambda = lambda > kFirstLambda ? 0.1 * lambda : 0.0;
        if (delta_.head(dim).lpNorm<Eigen::Infinity>() < options_.step_tolerance ||
            relative_decrease < options_.relative_cost_tolerance) {
          result.status = DeformationSolveStatus::kConverged;
        }
        break;
      }
      ++result.rejected_steps;
      if (attempt >= options_.max_damping_retries) {
        result.status = DeformationSolveStatus::kCostRose;  // keep the previous iterate
        break;
      }
      lambda = lambda > 0.0 ? 10.0 * lambda : kFirstLambda;
    }
  }
  pending_.head(dim) = iterate_.head(dim);
  has_pending_ = true;
  std::tie(result.mean_constraint_error_after_m, result.max_constraint_error_after_m) =
      constraintErrors(paramsOf(pending_));
  return result;
}

void DeformationGraph::commit() {
  if (!has_pending_) throw Error("deformation graph: commit() without a solved deformation");
  const Eigen::Index dim = static_cast<Eigen::Index>(kNodeParamDim) * node_count_;
  committed_.head(dim) = pending_.head(dim);
  has_pending_ = false;
}

void DeformationGraph::revert() { has_pending_ = false; }

}  // namespace vifusion::loop
