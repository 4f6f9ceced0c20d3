// Computes tokuyoshi2024 irradiance through the installed runtime and checks
// it against the exact pole E(1, κ) = 2π(κ − 1 + e^{−κ})/κ² (exit 0 on success).
#include <cmath>
#include <cstdio>

#include <sglab/sglab.hpp>

int main() {
  const double kappa = 4.0;
  const double exact =
      2 * 3.14159265358979323846 * (kappa - 1 + std::exp(-kappa)) / (kappa * kappa);
  const double e = sglab::irradiance_tokuyoshi2024(1.0, kappa);
  const float mid = sglab::irradiance_tokuyoshi2024(0.25f, 4.0f);
  std::printf("tokuyoshi2024(c=1, k=4) = %.17g (exact %.17g); (c=0.25) = %.9g\n", e, exact, mid);
  return std::abs(e - exact) <= 1e-14 * exact && std::isfinite(mid) && mid > 0 ? 0 : 1;
}
