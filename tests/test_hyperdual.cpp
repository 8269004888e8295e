// Hyper-dual numbers: exact first and second derivatives, mixed partials, the thesis' inverse.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "support.hpp"

namespace {

using H = dq::HyperDual<double>;

struct Case {
  std::string name;
  std::function<H(H)> f;
  std::function<double(double)> d1, d2;
  double lo, hi;
};

std::vector<Case> cases() {
  return {
      {"sqrt", [](H x) { return sqrt(x); }, [](double x) { return 0.5 / std::sqrt(x); },
       [](double x) { return -0.25 / (x * std::sqrt(x)); }, 0.2, 9},
      {"cbrt", [](H x) { return cbrt(x); }, [](double x) { return 1 / (3 * std::pow(x, 2.0 / 3)); },
       [](double x) { return -2 / (9 * std::pow(x, 5.0 / 3)); }, 0.2, 9},
      {"exp", [](H x) { return exp(x); }, [](double x) { return std::exp(x); }, [](double x) { return std::exp(x); }, -3, 3},
      {"log", [](H x) { return log(x); }, [](double x) { return 1 / x; }, [](double x) { return -1 / (x * x); }, 0.2, 9},
      {"log1p", [](H x) { return log1p(x); }, [](double x) { return 1 / (1 + x); },
       [](double x) { return -1 / ((1 + x) * (1 + x)); }, -0.5, 9},
      {"pow", [](H x) { return pow(x, 3.5); }, [](double x) { return 3.5 * std::pow(x, 2.5); },
       [](double x) { return 8.75 * std::pow(x, 1.5); }, 0.2, 3},
      {"pow_hd", [](H x) { return pow(x, x); }, [](double x) { return std::pow(x, x) * (std::log(x) + 1); },
       [](double x) { return std::pow(x, x) * ((std::log(x) + 1) * (std::log(x) + 1) + 1 / x); }, 0.2, 3},
      {"sin", [](H x) { return sin(x); }, [](double x) { return std::cos(x); }, [](double x) { return -std::sin(x); }, -4, 4},
      {"cos", [](H x) { return cos(x); }, [](double x) { return -std::sin(x); }, [](double x) { return -std::cos(x); }, -4, 4},
      {"tan", [](H x) { return tan(x); }, [](double x) { return 1 / std::pow(std::cos(x), 2); },
       [](double x) { return 2 * std::tan(x) / std::pow(std::cos(x), 2); }, -1.3, 1.3},
      {"asin", [](H x) { return asin(x); }, [](double x) { return 1 / std::sqrt(1 - x * x); },
       [](double x) { return x / std::pow(1 - x * x, 1.5); }, -0.9, 0.9},
      {"acos", [](H x) { return acos(x); }, [](double x) { return -1 / std::sqrt(1 - x * x); },
       [](double x) { return -x / std::pow(1 - x * x, 1.5); }, -0.9, 0.9},
      {"atan", [](H x) { return atan(x); }, [](double x) { return 1 / (1 + x * x); },
       [](double x) { return -2 * x / std::pow(1 + x * x, 2); }, -4, 4},
      {"atan2", [](H x) { return atan2(x, H(1.5)); }, [](double x) { return 1.5 / (2.25 + x * x); },
       [](double x) { return -3 * x / std::pow(2.25 + x * x, 2); }, -4, 4},
      {"sinh", [](H x) { return sinh(x); }, [](double x) { return std::cosh(x); }, [](double x) { return std::sinh(x); }, -3, 3},
      {"cosh", [](H x) { return cosh(x); }, [](double x) { return std::sinh(x); }, [](double x) { return std::cosh(x); }, -3, 3},
      {"tanh", [](H x) { return tanh(x); }, [](double x) { return 1 - std::pow(std::tanh(x), 2); },
       [](double x) { return -2 * std::tanh(x) * (1 - std::pow(std::tanh(x), 2)); }, -3, 3},
      {"asinh", [](H x) { return asinh(x); }, [](double x) { return 1 / std::sqrt(x * x + 1); },
       [](double x) { return -x / std::pow(x * x + 1, 1.5); }, -3, 3},
      {"acosh", [](H x) { return acosh(x); }, [](double x) { return 1 / std::sqrt(x * x - 1); },
       [](double x) { return -x / std::pow(x * x - 1, 1.5); }, 1.2, 5},
      {"atanh", [](H x) { return atanh(x); }, [](double x) { return 1 / (1 - x * x); },
       [](double x) { return 2 * x / std::pow(1 - x * x, 2); }, -0.9, 0.9},
      {"hypot", [](H x) { return hypot(x, H(2.0)); }, [](double x) { return x / std::hypot(x, 2.0); },
       [](double x) { return 4 / std::pow(x * x + 4, 1.5); }, -5, 5},
      {"inverse", [](H x) { return H(1) / x; }, [](double x) { return -1 / (x * x); },
       [](double x) { return 2 / (x * x * x); }, 0.3, 5},
  };
}

TEST(HyperDual, FirstAndSecondDerivativesAreExact) {
  dq::test::Random rng(11);
  for (const Case& c : cases()) {
    for (int i = 0; i < 200; ++i) {
      const double x = rng.uniform(c.lo, c.hi);
      const H y = c.f(H::variable(x));
      const double e1 = c.d1(x), e2 = c.d2(x);
      EXPECT_NEAR(y.e1, e1, 1e-12 * (1 + std::abs(e1))) << c.name << " at " << x;
      EXPECT_NEAR(y.e2, e1, 1e-12 * (1 + std::abs(e1))) << c.name << " at " << x;
      EXPECT_NEAR(y.e12, e2, 1e-11 * (1 + std::abs(e2))) << c.name << " at " << x;
    }
  }
}

TEST(HyperDual, MixedPartialsAreHessianEntries) {
  // f(x, y) = x² y³ + sin(x y): ∂²f/∂x∂y = 6 x y² + cos(xy) − x y sin(xy).
  auto f = [](H x, H y) { return x * x * y * y * y + sin(x * y); };
  for (double x : {-1.3, 0.2, 0.9})
    for (double y : {-0.7, 0.4, 2.1}) {
      const double expected = 6 * x * y * y + std::cos(x * y) - x * y * std::sin(x * y);
      EXPECT_NEAR(dq::mixed_derivative(f, x, y), expected, 1e-12 * (1 + std::abs(expected)));
    }
  // The same through atan2 with both arguments varying: ∂²/∂x∂y atan2(y, x) = (y² − x²)/(x² + y²)².
  auto g = [](H x, H y) { return atan2(y, x); };
  for (double x : {-1.3, 0.5})
    for (double y : {-0.7, 2.1})
      EXPECT_NEAR(dq::mixed_derivative(g, x, y), (y * y - x * x) / std::pow(x * x + y * y, 2), 1e-13);
}

TEST(HyperDual, InverseMatchesTheThesisFormula) {
  const H a(2, 3, 5, 7);
  const H inv = a.inverse();
  // 1/a − b/a² ε1 − c/a² ε2 + (2bc/a³ − d/a²) ε1ε2
  EXPECT_DOUBLE_EQ(inv.real, 0.5);
  EXPECT_DOUBLE_EQ(inv.e1, -0.75);
  EXPECT_DOUBLE_EQ(inv.e2, -1.25);
  EXPECT_DOUBLE_EQ(inv.e12, 2 * 3 * 5 / 8.0 - 7 / 4.0);
  const H one = a * inv;
  EXPECT_DOUBLE_EQ(one.real, 1);
  EXPECT_NEAR(one.e1, 0, 1e-15);
  EXPECT_NEAR(one.e2, 0, 1e-15);
  EXPECT_NEAR(one.e12, 0, 1e-15);
}

TEST(HyperDual, UnitsSquareToZeroButTheirProductDoesNot) {
  const H e1(0, 1, 0, 0), e2(0, 0, 1, 0);
  const H a = e1 * e1, b = e2 * e2, c = e1 * e2;
  EXPECT_EQ(a.real + a.e1 + a.e2 + a.e12, 0);
  EXPECT_EQ(b.real + b.e1 + b.e2 + b.e12, 0);
  EXPECT_EQ(c.e12, 1);
}

TEST(HyperDual, SecondDerivativeHelper) {
  EXPECT_NEAR(dq::second_derivative([](H x) { return exp(x * x); }, 0.5), (2 + 4 * 0.25) * std::exp(0.25), 1e-14);
}

}  // namespace
