// The one place SyROF chooses a CGAL kernel. Included only by the .cpp files
// of queries/ that use CGAL; nothing outside queries/src sees CGAL.
//
// Kernel: CGAL::Simple_cartesian over Int128, SyROF's exact integer. Points
// are integer millimetres, and every predicate the queries call
// (Left_turn_2, Orientation_2, Side_of_bounded_circle_2) is a ring
// expression in the coordinates (no division), so it is evaluated exactly:
// the same answer on every machine, no floating point, no filter, no GMP, no
// heap. Constructions that divide (circumcentres) are not taken from the
// kernel; the queries build them as exact rationals themselves.
#pragma once

// clang-format off
#include "cgal_config.h"  // first: how CGAL is configured for SyROF
// clang-format on

#include <CGAL/Simple_cartesian.h>
#include <CGAL/number_type_basic.h>

#include <utility>

#include "int128.h"

namespace CGAL {

// Int128 as a CGAL number type: an exact integral domain without division
// (ring operations and comparisons only), embedded in the reals.
template <>
class Algebraic_structure_traits<syrof::queries::internal::Int128>
    : public Algebraic_structure_traits_base<syrof::queries::internal::Int128, Integral_domain_without_division_tag> {
 public:
  typedef Tag_true Is_exact;
  typedef Tag_false Is_numerical_sensitive;
};

template <>
class Real_embeddable_traits<syrof::queries::internal::Int128>
    : public INTERN_RET::Real_embeddable_traits_base<syrof::queries::internal::Int128, Tag_true> {
 public:
  class Sgn : public CGAL::cpp98::unary_function<Type, ::CGAL::Sign> {
   public:
    ::CGAL::Sign operator()(const Type& x) const { return static_cast<::CGAL::Sign>(x.sign()); }
  };
  class To_double : public CGAL::cpp98::unary_function<Type, double> {
   public:
    double operator()(const Type& x) const { return x.to_double(); }
  };
  class To_interval : public CGAL::cpp98::unary_function<Type, std::pair<double, double>> {
   public:
    // Not used by any decision (the kernel is not filtered); a widened
    // interval around the nearest double keeps the contract.
    std::pair<double, double> operator()(const Type& x) const {
      const double value = x.to_double();
      const double slack = (value < 0 ? -value : value) * 1e-15 + 1.0;
      return {value - slack, value + slack};
    }
  };
};

}  // namespace CGAL

namespace syrof::queries::internal {

/// The kernel every CGAL call in queries/ uses.
typedef CGAL::Simple_cartesian<Int128> Kernel;

}  // namespace syrof::queries::internal
