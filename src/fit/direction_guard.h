// The pair guard of the refined fit (issue 18): a bound on how fast the refined directions may turn
// between neighbours, relative to the linear directions, so that the neighbour-angle p99 of a
// refined image is provably no worse than max(T, the linear fit's).
#pragma once
#include <cstddef>
#include <functional>
#include <vector>

#include "fit/fit_image.h"

namespace ahd {

// The angle in degrees between two stored directions, as direction_p99_angle_deg (fit_quality.h)
// measures it: acos of their dot product in double (clamped to [−1, 1]). Symmetric in u, v. The guard
// and the measure share it, so the guard's bound holds for the measure bit for bit.
double neighbour_angle_deg(const float u[3], const float v[3]);

// The pair guard over a refined fit (after the coherence pass). `linear_d` holds every texel's
// linear-fit d as fit_texel with DirectionFit::Linear stores it (3 floats a texel). For every pair
// of horizontally or vertically adjacent covered texels whose angle exceeds
// max(opt.pair_guard_deg, the angle between their linear d), both texels are replaced by their
// linear fit (fit_texel with DirectionFit::Linear: d, colours, ratio and flags exactly), repeated
// until no pair exceeds it. Reverting only grows the reverted set and a pair of two reverted texels
// has exactly its linear angle, so it terminates, and at the end every pair's angle a_i ≤
// max(T, l_i); hence every order statistic, in particular the p99, of the guarded field is at most
// max(T, the linear field's). Each sweep decides every texel from the previous sweep's state only,
// so the result does not depend on `threads`. Returns the number of texels reverted.
//
// The windowed fit's form: `revert(i)` is the fit a reverted texel i gets instead of its linear fit
// and must store exactly linear_d's direction for i (there: the linear d of the window's mean SH,
// colours on the texel's own SH); `also_d` (3 floats a texel: there, each texel's own linear d) is a
// second field whose angle also allows a pair to turn: a pair breaks the bound when its angle
// exceeds max(T, its angle in linear_d, its angle in also_d). The same argument then gives every
// pair's angle ≤ that maximum at the end. `revert` is called from several threads at once for
// different texels.
size_t guard_direction_pairs(const ShImage& sh, const FitOptions& opt, const std::vector<float>& linear_d,
                             int threads, AhdImage* fit, const std::function<AhdFit(size_t)>& revert = nullptr,
                             const std::vector<float>* also_d = nullptr);

}  // namespace ahd
