// Bump mapping (Blinn 1978; paper §4.1, image 14): the normal of the surface displaced along its
// unit normal by a height field, without displacing it.
#pragma once

#include <glm/glm.hpp>

namespace wf {

/// The unit normal of S + scale * h(u, v) * n (n = N / |N|) to first order in h, given the
/// surface's derivatives Su, Sv (any common space: world or eye) and (dh/du, dh/dv):
///
///     N' = |Su x Sv| n + sigma * scale * (h_u (n x Sv) - h_v (n x Su)),   normalised,
///
/// Blinn's perturbation, where sigma = sign((Su x Sv) . n) keeps it right for a normal given
/// against the parametric orientation (a reversed face). The term h * dn/du that Blinn drops is
/// of relative size h times the curvature. N may have any length (only its direction is used).
/// Returns n unchanged when the gradient is zero, and falls back to n when Su or Sv is zero or
/// parallel (a pole), the gradient or scale is not finite, or the result degenerates; returns
/// (0, 0, 1) only when N itself has no direction and Su x Sv has none either.
glm::dvec3 bumpNormal(const glm::dvec3& N, const glm::dvec3& Su, const glm::dvec3& Sv,
                      glm::dvec2 heightGradient, double scale);

}  // namespace wf
