#pragma once
// Central-difference Jacobians for checking analytic ones in tests:
//
//   J = ∂f(x ⊞ δ)/∂δ at δ = 0,   column i = (f(x ⊞ h·eᵢ) − f(x ⊞ −h·eᵢ)) / 2h.
//
// x lives on any manifold given by a "plus" (x, δ) → x'; f must return an Eigen column vector. For a
// manifold-valued function g, differentiate its tangent-space difference, e.g.
//   numericJacobian<18>([&](const NavState& s) { return boxMinus(g(s), g(x0)); }, x0,
//                       [](const NavState& s, const Vector18d& d) { return boxPlus(s, d); });
// Sizes known at compile time give fixed-size results. The truncation error is O(h²·|f'''|) and the
// rounding error O(ε·|f|/h): about 1e-9 for O(1) quantities with the default h = 1e-6, so analytic
// Jacobians are compared with tolerances of 1e-7..1e-6 (scaled by the size of the entries).

#include <Eigen/Core>
#include <type_traits>

namespace vifusion {

inline constexpr double kDefaultNumericStep = 1e-6;

namespace detail {

template <int kIn, class F, class X, class Plus>
auto numericJacobianImpl(const F& f, const X& x, const Plus& plus, int dim, double step) {
  using Delta = Eigen::Matrix<double, kIn, 1>;
  using Out = std::decay_t<decltype(f(plus(x, Delta::Zero(dim).eval())))>;
  static_assert(Out::ColsAtCompileTime == 1,
                "f must return a column vector (map manifold outputs to a tangent vector)");
  constexpr int kOut = Out::RowsAtCompileTime;
  using OutVector = Eigen::Matrix<double, kOut, 1>;

  Delta delta = Delta::Zero(dim);
  Eigen::Matrix<double, kOut, kIn> J;
  for (int i = 0; i < dim; ++i) {
    delta[i] = step;
    const OutVector f_plus = f(plus(x, delta));
    delta[i] = -step;
    const OutVector f_minus = f(plus(x, delta));
    delta[i] = 0.0;
    if (i == 0) J.resize(f_plus.rows(), dim);  // sizes only matter when dynamic
    J.col(i) = (f_plus - f_minus) / (2.0 * step);
  }
  return J;
}

}  // namespace detail

/// Jacobian of f at x w.r.t. a kIn-dimensional perturbation applied with plus(x, δ).
template <int kIn, class F, class X, class Plus>
auto numericJacobian(const F& f, const X& x, const Plus& plus, double step = kDefaultNumericStep) {
  static_assert(kIn > 0, "the perturbation dimension must be known at compile time");
  return detail::numericJacobianImpl<kIn>(f, x, plus, kIn, step);
}

/// Jacobian of f at an Eigen vector x, perturbed by ordinary addition.
template <class F, class Derived>
auto numericJacobian(const F& f, const Eigen::MatrixBase<Derived>& x, double step = kDefaultNumericStep) {
  static_assert(Derived::ColsAtCompileTime == 1, "x must be a column vector");
  using X = Eigen::Matrix<double, Derived::RowsAtCompileTime, 1>;
  const auto add = [](const X& x0, const X& d) -> X { return x0 + d; };
  return detail::numericJacobianImpl<Derived::RowsAtCompileTime>(f, X(x), add, static_cast<int>(x.rows()), step);
}

}  // namespace vifusion
