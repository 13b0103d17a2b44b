#pragma once
// A cylinder in any orientation (a can, a tin or a jar lying on its side, a bottle
// leaning), for ObjectShapeRecognizer: the axis is the direction every side normal is
// perpendicular to, the cross-section a circle fitted across it. Private to runtime.

#include <functional>
#include <vector>

#include "annex/common/physical_scene.h"
#include "annex/runtime/object_shape_recognizer.h"

namespace annex {

struct AxisCylinderFit {
  bool valid = false;
  ShapeFit fit;          // kind cylinder, dimensions {radius, length}, axis, coverage
  double score = 0;      // MSAC score, 1 - (d / tol)^2 per explained point, over all points
  // |mean of e^(4i psi)| over the side normals' angles psi about the axis: near 1 when
  // they bunch into two faces 90 degrees apart (a box seen along an edge), near 0 when
  // they sweep round (a cylinder seen over a quarter turn or more).
  double facetedness = 1;
};

// The caller's test of a fit's axis before the fit's costliest passes: false when no
// cylinder with this axis could be chosen (ObjectShapeRecognizer takes only a lying
// one). Given (non-empty), a fit whose result could not be chosen is not finished and
// comes back invalid: fit_cylinder_any_axis when no start has an axis the test takes
// and side normals less faceted than params.max_round_facetedness (the better scoring
// start is the fit, so both are fitted when either could win); fit_cylinder_on_rim
// when the lid's axis fails the test or the round outline is below
// params.min_round_outline. Empty: every fit is finished.
using AxisGate = std::function<bool(Vec3 axis)>;

// points, normals (same size, unit, 0 where unknown) and per-point tolerances.
AxisCylinderFit fit_cylinder_any_axis(const std::vector<Vec3>& points,
                                      const std::vector<Vec3>& normals,
                                      const std::vector<double>& tolerance,
                                      const ShapeRecognizerParams& params,
                                      const AxisGate& could_win = {});

// A short wide cylinder on its rim or lying with its lid to the camera (a cookie tin on
// its edge): the lid is a flat disc, so the axis is the normal of the points' flattest
// direction (the lid's plane refitted on its own points; an embossed lid's normals
// scatter, its points do not), and the outline of the points seen along that axis is a
// circle. `round_outline` is the share of outline directions on the fitted circle.
struct DiscCylinderFit {
  AxisCylinderFit cylinder;
  double round_outline = 0;
};
DiscCylinderFit fit_cylinder_on_rim(const std::vector<Vec3>& points,
                                    const std::vector<double>& tolerance,
                                    const ShapeRecognizerParams& params,
                                    const AxisGate& could_win = {});

}  // namespace annex
