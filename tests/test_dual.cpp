// Dual numbers: arithmetic, and derivatives of every elementary function against analytic ones.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "support.hpp"

namespace {

using dq::Dual;
using D = Dual<double>;

static_assert(D(2, 3) * D(4, 5) == D(8, 22));  // compile-time arithmetic (comparison is on values)
static_assert((D(2, 3) * D(4, 5)).dual == 22);
static_assert((D(1, 2) / D(2, 0)).dual == 1);

TEST(Dual, EpsilonSquaresToZero) {
  const D eps(0, 1);
  const D sq = eps * eps;
  EXPECT_EQ(sq.real, 0.0);
  EXPECT_EQ(sq.dual, 0.0);
}

TEST(Dual, DivisionIsInverseOfMultiplication) {
  dq::test::Random rng(1);
  for (int i = 0; i < 1000; ++i) {
    const D a(rng.uniform(-5.0, 5.0), rng.uniform(-5.0, 5.0));
    D b(rng.uniform(0.5, 5.0), rng.uniform(-5.0, 5.0));
    const D back = (a / b) * b;
    EXPECT_NEAR(back.real, a.real, 1e-14);
    EXPECT_NEAR(back.dual, a.dual, 1e-13);
  }
}

struct Case {
  std::string name;
  std::function<D(D)> f;
  std::function<double(double)> df;  // analytic derivative
  double lo, hi;
};

std::vector<Case> cases() {
  using std::cos;
  using std::sin;
  return {
      {"sqrt", [](D x) { return sqrt(x); }, [](double x) { return 0.5 / std::sqrt(x); }, 0.1, 9},
      {"cbrt", [](D x) { return cbrt(x); }, [](double x) { return 1 / (3 * std::cbrt(x) * std::cbrt(x)); }, 0.1, 9},
      {"exp", [](D x) { return exp(x); }, [](double x) { return std::exp(x); }, -3, 3},
      {"expm1", [](D x) { return expm1(x); }, [](double x) { return std::exp(x); }, -3, 3},
      {"log", [](D x) { return log(x); }, [](double x) { return 1 / x; }, 0.1, 9},
      {"log1p", [](D x) { return log1p(x); }, [](double x) { return 1 / (1 + x); }, -0.9, 9},
      {"pow_scalar", [](D x) { return pow(x, 2.5); }, [](double x) { return 2.5 * std::pow(x, 1.5); }, 0.1, 4},
      {"pow_base", [](D x) { return pow(3.0, x); }, [](double x) { return std::pow(3.0, x) * std::log(3.0); }, -2, 2},
      {"pow_dual", [](D x) { return pow(x, x); }, [](double x) { return std::pow(x, x) * (std::log(x) + 1); }, 0.1, 3},
      {"sin", [](D x) { return sin(x); }, [](double x) { return std::cos(x); }, -4, 4},
      {"cos", [](D x) { return cos(x); }, [](double x) { return -std::sin(x); }, -4, 4},
      {"tan", [](D x) { return tan(x); }, [](double x) { return 1 / (std::cos(x) * std::cos(x)); }, -1.4, 1.4},
      {"asin", [](D x) { return asin(x); }, [](double x) { return 1 / std::sqrt(1 - x * x); }, -0.95, 0.95},
      {"acos", [](D x) { return acos(x); }, [](double x) { return -1 / std::sqrt(1 - x * x); }, -0.95, 0.95},
      {"atan", [](D x) { return atan(x); }, [](double x) { return 1 / (1 + x * x); }, -5, 5},
      {"atan2_y", [](D x) { return atan2(x, D(1.5)); }, [](double x) { return 1.5 / (2.25 + x * x); }, -5, 5},
      {"atan2_x", [](D x) { return atan2(D(0.7), x); }, [](double x) { return -0.7 / (0.49 + x * x); }, -5, 5},
      {"sinh", [](D x) { return sinh(x); }, [](double x) { return std::cosh(x); }, -3, 3},
      {"cosh", [](D x) { return cosh(x); }, [](double x) { return std::sinh(x); }, -3, 3},
      {"tanh", [](D x) { return tanh(x); }, [](double x) { return 1 / (std::cosh(x) * std::cosh(x)); }, -3, 3},
      {"asinh", [](D x) { return asinh(x); }, [](double x) { return 1 / std::sqrt(x * x + 1); }, -3, 3},
      {"acosh", [](D x) { return acosh(x); }, [](double x) { return 1 / std::sqrt(x * x - 1); }, 1.1, 5},
      {"atanh", [](D x) { return atanh(x); }, [](double x) { return 1 / (1 - x * x); }, -0.9, 0.9},
      {"hypot", [](D x) { return hypot(x, D(2.0)); }, [](double x) { return x / std::hypot(x, 2.0); }, -5, 5},
      {"abs", [](D x) { return abs(x); }, [](double x) { return x < 0 ? -1.0 : 1.0; }, -5, 5},
      {"min", [](D x) { return min(x, D(0.5)); }, [](double x) { return x < 0.5 ? 1.0 : 0.0; }, -5, 5},
      {"max", [](D x) { return max(x, D(0.5)); }, [](double x) { return x > 0.5 ? 1.0 : 0.0; }, -5, 5},
      {"floor", [](D x) { return floor(x); }, [](double) { return 0.0; }, -5, 5},
      {"ceil", [](D x) { return ceil(x); }, [](double) { return 0.0; }, -5, 5},
      {"round", [](D x) { return round(x); }, [](double) { return 0.0; }, -5, 5},
      {"trunc", [](D x) { return trunc(x); }, [](double) { return 0.0; }, -5, 5},
      {"fmod", [](D x) { return fmod(x, D(1.25)); }, [](double) { return 1.0; }, -5, 5},
      {"composite", [](D x) { return sin(x) * exp(x) / (D(1) + x * x); },
       [](double x) {
         const double u = std::sin(x) * std::exp(x), du = (std::cos(x) + std::sin(x)) * std::exp(x);
         return (du * (1 + x * x) - u * 2 * x) / ((1 + x * x) * (1 + x * x));
       },
       -3, 3},
  };
}

TEST(Dual, EveryFunctionGivesTheAnalyticDerivative) {
  dq::test::Random rng(2);
  for (const Case& c : cases()) {
    for (int i = 0; i < 200; ++i) {
      const double x = rng.uniform(c.lo, c.hi);
      const D y = c.f(D::variable(x));
      const double expected = c.df(x);
      EXPECT_NEAR(y.dual, expected, 1e-12 * (1 + std::abs(expected))) << c.name << " at " << x;
    }
  }
}

TEST(Dual, ValuePartEqualsThePlainFunction) {
  dq::test::Random rng(3);
  for (const Case& c : cases()) {
    const double x = rng.uniform(c.lo, c.hi);
    const D y = c.f(D(x, 0));
    EXPECT_EQ(y.dual, 0.0) << c.name;  // constants have no derivative
  }
  EXPECT_EQ(dq::sin(D(0.3)).real, std::sin(0.3));
  EXPECT_EQ(dq::exp(D(0.3)).real, std::exp(0.3));
}

TEST(Dual, NestedDualGivesSecondDerivatives) {
  using DD = Dual<D>;
  // f(x) = x^3 sin x; f'' = 6x sin x + 6x^2 cos x − x^3 sin x.
  for (double x : {-2.0, -0.3, 0.7, 1.9}) {
    const DD v(D(x, 1), D(1, 0));  // x + ε1 + ε2
    const DD y = v * v * v * sin(v);
    const double f2 = 6 * x * std::sin(x) + 6 * x * x * std::cos(x) - x * x * x * std::sin(x);
    const double f1 = 3 * x * x * std::sin(x) + x * x * x * std::cos(x);
    EXPECT_NEAR(y.dual.dual, f2, 1e-12 * (1 + std::abs(f2)));
    EXPECT_NEAR(y.real.dual, f1, 1e-12 * (1 + std::abs(f1)));
    EXPECT_NEAR(y.dual.real, f1, 1e-12 * (1 + std::abs(f1)));
  }
}

TEST(Dual, DerivativeHelperAndFloat) {
  const float d = dq::derivative([](Dual<float> x) { return x * x * x; }, 2.0f);
  EXPECT_FLOAT_EQ(d, 12.0f);
  const long double e = dq::derivative([](Dual<long double> x) { return exp(x); }, 1.0L);
  DQ_EXPECT_NEAR(e, std::exp(1.0), 1e-15);
}

TEST(Dual, SqrtOfConstantZeroHasNoNaN) {
  const D r = dq::sqrt(D(0.0, 0.0));
  EXPECT_EQ(r.real, 0.0);
  EXPECT_EQ(r.dual, 0.0);
  EXPECT_TRUE(std::isinf(dq::sqrt(D(0.0, 1.0)).dual));  // d√x/dx at 0 is infinite, as for reals
}

TEST(Dual, HypotAtTheOriginHasTheOneSidedDerivative) {
  const D h = dq::hypot(D(0, 3), D(0, 4));  // |ε(3, 4)| = 5ε
  EXPECT_EQ(h.real, 0);
  EXPECT_EQ(h.dual, 5);
}

TEST(Dual, NaNPropagates) {
  const D n(std::numeric_limits<double>::quiet_NaN(), 1);
  EXPECT_TRUE(dq::isnan(dq::sin(n)));
  EXPECT_TRUE(dq::isnan(n * D(2)));
}

TEST(Dual, DualConjugateAndComparisons) {
  const D a(1, 2);
  EXPECT_EQ(a.conjugate().dual, -2);
  EXPECT_EQ((a * a.conjugate()).dual, 0);  // (a + εb)(a − εb) = a²
  EXPECT_TRUE(D(1, 5) < D(2, -5));
  EXPECT_TRUE(D(1, 5) == D(1, -5));  // compares values only, by design
}

}  // namespace
