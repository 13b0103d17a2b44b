#pragma once
// Labels on run's overlay images: which virtual object is annexed onto which prop,
// with its vote and tracking state ("champagne_bottle on p1 84.05 tracking"), beside
// the overlay in each eye's part of the image, laid out as the scan picture's labels
// are (inside the image, over no other label while there is room; docs/renderer.md).

#include <span>
#include <string>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/runtime/annex_session.h"
#include "annex/runtime/renderer.h"

namespace annex {

// "champagne_bottle on p1 84.05 tracking", "... clamped held": the vote as run prints it.
std::string overlay_label_text(const AnnexedObject& object);

struct OverlayLabel {
  std::string text;
  std::vector<Vec3> points;  // sensor frame: where the overlay is drawn (its mesh's vertices)
  bool dim = false;          // drawn grey (a held pose, a guess)
};

// Draws each label next to the pixel bounds of its points' projection in each eye
// (eyes side by side from left to right, as Renderer::render lays them out). A label
// whose points are all behind an eye or outside its view is left out of that eye.
void draw_overlay_labels(RgbaImage& image, std::span<const Eye> eyes,
                         const std::vector<OverlayLabel>& labels);

// Up to `max_points` of a mesh's vertices, evenly spread through its vertex list:
// enough for a label's bounds, few enough to project every frame.
std::vector<Vec3> label_points(const MeshData& mesh, std::size_t max_points = 600);

}  // namespace annex
