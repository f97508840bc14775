#pragma once
// The deformation graph of loop closure (ElasticFusion; Laidlow et al. 2017 §V): nodes sampled from the
// map, connected to their temporal neighbours, each with an affine map (A_i, t_i); optimised by sparse
// Gauss-Newton so that constraint points move to their targets while the deformation stays locally rigid
// (E_rot), smooth (E_reg) and, the paper's addition, gravity-consistent (E_imu). Terms and Jacobians:
// deformation_energy.hpp; φ: deformation_function.hpp; binding: node_binding.hpp.
//
// Use (one loop closure):
//   graph.build(samples);               // nodes from map points (position in W, creation frame index)
//   graph.setGravity(g_W);              // [m/s², W]; zero = no gravity term
//   graph.addConstraint(s, t_s, d);     // E_con: φ(s) → d;   addPin(p, t): φ(p) = p;   addRelative(a, t_a, b, t_b)
//   const auto result = graph.solve();  // never changes what deformPoint() & co. apply
//   if (accept(result)) graph.commit(); else graph.revert();
//   surfel' = graph.deformPoint(surfel, surfel_time), normals and poses likewise.
//
// Commit/revert: solve() starts from the committed parameters (identity after build()) and leaves its best
// iterate as the *pending* parameter set; the deform*() functions keep using the committed set until
// commit(). A failed solve (kNumericalFailure, kNoConstraints) leaves no pending set. So the graph's
// applied deformation changes only by an explicit commit(), never by a solve, failed or not.
//
// Memory: the constructor allocates everything sized by the options (nodes, edges, parameter vectors,
// constraints: max_nodes and max_constraints; the normal equations and their factor for the band of
// max(neighbours_per_side, candidates − 1) blocks, deformation_solver.hpp: about 53 MB at 1024 nodes and
// window 20). build(), the add*() functions and solve() only write into it: nothing allocates after
// construction. Capacity overflow throws vifusion::Error naming the capacity, except a
// pattern beyond the solver's (E_rel between windows far apart in time): solve() reports kNumericalFailure.
//
// Not thread-safe; one graph per loop-closure thread.

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "vifusion/core/se3.hpp"
#include "vifusion/loop/deformation_energy.hpp"
#include "vifusion/loop/deformation_function.hpp"
#include "vifusion/loop/deformation_solver.hpp"
#include "vifusion/loop/node_binding.hpp"

namespace vifusion::loop {

struct DeformationGraphOptions {
  /// Node capacity, fixed at construction (ElasticFusion: 1024, a texture-packing limit we do not have).
  /// Memory and solve time grow with it: about 1000 nodes keep a solve well under a second on one core.
  /// In [kBoundNodes + 1, 1'000'000] (the upper bound keeps the sparse matrix's int indices in range).
  int max_nodes = 1024;
  /// Take every sample_stride-th input sample as a node; build() raises the stride to
  /// ceil(samples / max_nodes) when needed so that at most max_nodes nodes are taken. ≥ 1.
  int sample_stride = 1;
  /// Temporal neighbours per side in E_reg: node l is linked to the neighbours_per_side nodes before and
  /// after it in creation time (ElasticFusion: 2, i.e. 4 neighbours). In [1, 16].
  int neighbours_per_side = 2;
  /// Binding window (node_binding.hpp): nodes around the point's time among which the kBoundNodes nearest
  /// are chosen (ElasticFusion: 20). ≥ kBoundNodes + 1; a window wider than the graph takes all nodes.
  int candidates = 20;
  /// Constraint capacity (E_con, E_pin and E_rel together), fixed at construction. ≥ 1.
  int max_constraints = 4096;
  /// Weights of the paper's eq. 16–17 (ElasticFusion's): ω_f (E_rot), ω_r (E_reg), ω_c (E_con, E_pin, E_rel)
  /// and ω_i (E_imu). All ≥ 0 and finite; weight_con > 0 (without it nothing moves the graph).
  double weight_rot = 1.0;
  double weight_reg = 10.0;
  double weight_con = 100.0;
  double weight_imu = 100.0;
  /// The paper's gravity term E_imu; off reproduces ElasticFusion (the ablation).
  bool use_gravity_term = true;
  /// Gauss-Newton iterations (linearisations) at most. ElasticFusion stops after 3. All terms but E_rot are
  /// linear in the parameters, so undamped steps converge in 3–5 (4 on the unit tests' room); the limit is
  /// 10 because steps retried with damping (max_damping_retries) are shorter and a solve that needed them
  /// takes more to reach sub-millimetre constraint errors. A converged solve stops earlier. ≥ 1.
  int max_iterations = 10;
  /// A step that raises the cost is retried on the same linearisation with Levenberg-Marquardt damping
  /// λ·diag(H), λ = 1e-4, 1e-3, … at most this many times before the solve stops and keeps the previous
  /// iterate. Why: nodes whose temporal neighbours lie on one line (a wall strip created in one frame, all
  /// neighbours above each other) have a rotation about that line that E_reg and the linearised E_rot do not
  /// see, so the plain Gauss-Newton step can turn them by radians and E_rot's true cost then rises; with
  /// gravity along that line (vertical walls, E_imu on) this happens on ordinary loop closures. 0 gives
  /// ElasticFusion's rule: stop at the first rise. λ returns to 0 (plain Gauss-Newton) after steps that
  /// pass at once. In [0, 30].
  int max_damping_retries = 8;
  /// Converged when the largest step entry |δ|∞ is below this (A entries are unitless, t in m: 1e-7 is
  /// 0.1 µm, four orders below the map's millimetre; ElasticFusion's 1e-2 on ‖δ‖ leaves millimetre-level
  /// errors). ≥ 0.
  double step_tolerance = 1e-7;
  /// Converged when the cost decreases by less than this fraction in one step (ElasticFusion: 1e-5). ≥ 0.
  double relative_cost_tolerance = 1e-9;
  /// Converged when the cost is below this (ElasticFusion: 1e-3; in units of ω·m², 1e-12 is a 0.1 µm
  /// constraint error at ω_con = 100). ≥ 0.
  double absolute_cost_tolerance = 1e-12;
  /// Added to H's diagonal: makes H positive definite when the constraints leave a direction free (a node
  /// whose temporal neighbours are collinear can turn about that line at no cost), without a measurable
  /// bias: H's entries are O(1…100). ≥ 0.
  double damping = 1e-9;

  /// @throws vifusion::Error naming the first field out of its range.
  void validate() const;
};

/// A map point offered as a node: position in W [m] and creation time (frame index).
struct NodeSample {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();
  std::uint32_t time = 0;
};

enum class DeformationSolveStatus {
  kConverged,         ///< a tolerance was met; the pending set is the solution
  kMaxIterations,     ///< stopped at max_iterations; the pending set is the last (best) iterate
  kCostRose,          ///< a step increased the cost; the pending set is the previous (best) iterate
  kNumericalFailure,  ///< non-finite cost, a failed factorisation or a pattern beyond capacity; no pending set
  kNoConstraints,     ///< nothing to solve for; no pending set
};

const char* deformationSolveStatusName(DeformationSolveStatus status);

/// Weighted contribution of each term to the energy, ω_x·Σ‖r_x‖² (m² times the weight; E_imu in (m/s²)²).
struct DeformationTermCosts {
  double rot = 0.0;
  double reg = 0.0;
  double con = 0.0;
  double pin = 0.0;
  double rel = 0.0;
  double imu = 0.0;
  double total() const { return rot + reg + con + pin + rel + imu; }
};

struct DeformationSolveResult {
  DeformationSolveStatus status = DeformationSolveStatus::kNoConstraints;
  int iterations = 0;      ///< accepted steps (one linearisation each)
  int rejected_steps = 0;  ///< steps that raised the cost and were retried with more damping or ended the solve
  DeformationTermCosts initial_cost;
  DeformationTermCosts final_cost;  ///< at the pending set (= initial_cost when no step was accepted)
  /// ‖φ(source) − target‖ over the E_con constraints [m], before (committed set) and after (pending set):
  /// what an acceptance test reads (ElasticFusion accepts a global closure only with a small mean after).
  /// 0 without E_con constraints.
  double mean_constraint_error_before_m = 0.0;
  double max_constraint_error_before_m = 0.0;
  double mean_constraint_error_after_m = 0.0;
  double max_constraint_error_after_m = 0.0;

  /// A pending set exists (commit() may be called).
  bool hasSolution() const {
    return status != DeformationSolveStatus::kNumericalFailure && status != DeformationSolveStatus::kNoConstraints;
  }
};

class DeformationGraph {
 public:
  /// Validates the options and allocates for max_nodes nodes and max_constraints constraints.
  explicit DeformationGraph(const DeformationGraphOptions& options = {});

  const DeformationGraphOptions& options() const { return options_; }

  /// (Re)builds the nodes from map samples in any order (e.g. the surfel buffer's): every stride-th sample
  /// (stride from the options), sorted by time (ties by input order, so the result is deterministic), with
  /// temporal-neighbour edges. Clears the constraints and resets the deformation to identity.
  ///
  /// Nodes created before `free_from_time` (a frame index; 0: none) are held at the identity by solve(): after
  /// a closure has corrected the map up to its frame, a later one moves only what was mapped since
  /// (ElasticFusion's rule for every local closure after the first). Without it each closure's few constraints
  /// leave the old map's nodes to the regularisers alone, and they drift a little at every closure.
  /// @throws vifusion::Error when fewer than kBoundNodes + 1 nodes result or a sample is not finite.
  void build(std::span<const NodeSample> samples, std::uint32_t free_from_time = 0);

  int nodeCount() const { return node_count_; }
  /// Nodes [0, firstFreeNode()) are held (created before build()'s free_from_time); the rest are solved for.
  int firstFreeNode() const { return first_free_node_; }
  /// Node positions g_i in W [m] and times, sorted by time.
  std::span<const Eigen::Vector3d> nodePositions() const;
  std::span<const std::uint32_t> nodeTimes() const;
  /// Directed E_reg edges (l, n) in node indices.
  std::span<const std::pair<int, int>> edges() const;
  /// The committed parameters, 12 per node (layout in deformation_function.hpp).
  std::span<const double> parameters() const;
  /// The pending parameters of the last solve(); empty when there are none.
  std::span<const double> pendingParameters() const;

  /// Gravity in W [m/s²] for E_imu (the paper's _W g); zero (the default) makes E_imu vanish.
  void setGravity(const Eigen::Vector3d& g_W);
  const Eigen::Vector3d& gravity() const { return g_W_; }

  /// E_con: φ(source_W) should reach target_W [m]; the source is bound with source_time.
  /// @throws vifusion::Error when the graph is not built, a point is not finite or max_constraints is reached.
  void addConstraint(const Eigen::Vector3d& source_W, std::uint32_t source_time, const Eigen::Vector3d& target_W);
  /// E_pin: φ(p_W) should stay at p_W. Throws as addConstraint().
  void addPin(const Eigen::Vector3d& p_W, std::uint32_t time);
  /// E_rel: φ(a_W) and φ(b_W) should coincide (both deformed). Throws as addConstraint().
  void addRelative(const Eigen::Vector3d& a_W, std::uint32_t time_a, const Eigen::Vector3d& b_W, std::uint32_t time_b);
  void clearConstraints();
  /// Constraints of all kinds added since build() or clearConstraints().
  int constraintCount() const { return static_cast<int>(constraints_.size()); }

  /// Gauss-Newton from the committed parameters; see the top of this file for what it changes (only the
  /// pending set). @throws vifusion::Error when the graph is not built.
  DeformationSolveResult solve();
  /// Makes the pending set the committed one. @throws vifusion::Error when there is no pending set.
  void commit();
  /// Drops the pending set.
  void revert();
  bool hasPending() const { return has_pending_; }

  /// Energy terms at the committed parameters.
  DeformationTermCosts cost() const;

  /// Binding of a point with its creation time (node_binding.hpp). Requires a built graph.
  NodeBinding<double> bind(const Eigen::Vector3d& p_W, std::uint32_t time) const;
  /// φ with the committed parameters, for points [m, W], normals (unit, W) and camera poses T_W_C.
  Eigen::Vector3d deformPoint(const Eigen::Vector3d& p_W, std::uint32_t time) const;
  Eigen::Vector3d deformNormal(const Eigen::Vector3d& n_W, const Eigen::Vector3d& p_W, std::uint32_t time) const;
  SE3d deformPose(const SE3d& T_W_C, std::uint32_t time) const;

 private:
  enum class Kind { kCon, kPin, kRel };
  struct Constraint {
    Kind kind = Kind::kCon;
    Eigen::Vector3d a_W = Eigen::Vector3d::Zero();  ///< source (con), point (pin), a (rel)
    Eigen::Vector3d b_W = Eigen::Vector3d::Zero();  ///< target (con), b (rel)
    NodeBinding<double> binding_a;
    NodeBinding<double> binding_b;  ///< rel only
  };

  void requireBuilt(const char* what) const;
  void pushConstraint(const Constraint& c);
  std::span<const double> paramsOf(const Eigen::VectorXd& x) const;
  DeformationTermCosts evaluate(std::span<const double> x) const;
  /// Mean and max ‖φ(source) − target‖ over E_con [m].
  std::pair<double, double> constraintErrors(std::span<const double> x) const;
  void linearize(std::span<const double> x);
  /// system_'s addBlock/addGradient, skipping held nodes (firstFreeNode()).
  void addBlock(int i, int j, const Matrix12d& H_block);
  void addGradient(int i, const Vector12d& b_block);
  /// False when the pattern exceeds the solver's capacity.
  bool buildPattern();
  void addPointTerm(const NodeBinding<double>* bindings, const PointJacobians* J, int count, const Eigen::Vector3d& r,
                    double weight);

  DeformationGraphOptions options_;
  int node_count_ = 0;
  int first_free_node_ = 0;
  std::vector<Eigen::Vector3d> positions_W_;  ///< capacity max_nodes
  std::vector<std::uint32_t> times_;
  std::vector<int> order_;                  ///< build() scratch: sample indices being sorted
  std::vector<std::pair<int, int>> edges_;  ///< directed (l, n)
  std::vector<Constraint> constraints_;     ///< capacity max_constraints
  Eigen::Vector3d g_W_ = Eigen::Vector3d::Zero();

  Eigen::VectorXd committed_;  ///< 12·max_nodes; the first 12·node_count_ are in use
  Eigen::VectorXd pending_;
  Eigen::VectorXd iterate_;
  Eigen::VectorXd trial_;
  Eigen::VectorXd delta_;
  bool has_pending_ = false;

  BlockSparseSystem system_;
  std::vector<std::pair<int, int>> pattern_pairs_;  ///< the solver's block pattern; reserved at construction
  bool pattern_dirty_ = true;
};

}  // namespace vifusion::loop
