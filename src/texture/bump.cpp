#include "texture/bump.h"

#include "core/numeric.h"

#include <cmath>

namespace wf {
glm::dvec3 bumpNormal(const glm::dvec3& N, const glm::dvec3& Su, const glm::dvec3& Sv,
                      glm::dvec2 heightGradient, double scale) {
  const bool derivativesFinite = finite3(Su) && finite3(Sv);
  const glm::dvec3 A = derivativesFinite ? glm::cross(Su, Sv) : glm::dvec3(0.0);
  const double lengthA = glm::length(A);
  // The unperturbed unit normal: N's direction, else the parametric one, else +z.
  const double lengthN = finite3(N) ? glm::length(N) : 0.0;
  glm::dvec3 n;
  if (lengthN > 0.0 && std::isfinite(lengthN))
    n = N / lengthN;
  else if (lengthA > 0.0 && std::isfinite(lengthA))
    n = A / lengthA;
  else
    return {0.0, 0.0, 1.0};

  const double hu = scale * heightGradient.x, hv = scale * heightGradient.y;
  if (!std::isfinite(hu) || !std::isfinite(hv) || (hu == 0.0 && hv == 0.0)) return n;
  // Degenerate parametrisation (pole, cusp): no tangent plane to tilt within.
  const double lengthsProduct = glm::length(Su) * glm::length(Sv);
  if (!(lengthA > 1e-12 * lengthsProduct) || !std::isfinite(lengthA)) return n;

  const double sigma = glm::dot(A, n) < 0.0 ? -1.0 : 1.0;
  const glm::dvec3 perturbed =
      lengthA * n + sigma * (hu * glm::cross(n, Sv) - hv * glm::cross(n, Su));
  const double length = glm::length(perturbed);
  if (!(length > 0.0) || !std::isfinite(length)) return n;
  return perturbed / length;
}

}  // namespace wf
