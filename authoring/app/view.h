#pragma once
// Where things are on screen: the fixed panel layout around the viewport, the
// placement of objects in the world and the camera's matrices. Shared by the
// panels (hit tests, handles) and the GL renderer.

#include <vector>

#include <imgui.h>
#include <glm/glm.hpp>

#include "annex/authoring/editor_document.h"
#include "ui_state.h"

namespace annex::authoring {

// Debian's ImGui 1.86 has no docking: panels sit at fixed places around the viewport.
Layout compute_layout(float width, float height, float menu_height);

glm::mat4 view_matrix(const Camera& c);
glm::mat4 projection_matrix(const Camera& c, float aspect);
glm::vec3 camera_position(const Camera& c);

// One drawn copy of a virtual object: which object, at which world transform, and
// (for the scaling-limits preview) with which label.
struct Placement {
  int object = -1;
  glm::mat4 model{1.f};
  const char* label = nullptr;  // "min" / "max" for the limits preview
  bool ghost = false;
};

// Objects stand side by side along X in spec order. With the limits preview on,
// the selected object alone is shown between copies at its min and max scale.
std::vector<Placement> place_objects(const EditorDocument& doc, const UiState& ui);

// World transform of a primitive inside a placement.
glm::mat4 primitive_matrix(const Primitive& p);
glm::mat4 to_mat4(const Pose& pose);

// Scale of an object at its salient primitive's min or max limits, in that primitive's
// frame: (x, y, z) factors for its local axes (z is the primitive's axis).
glm::vec3 limit_scale(const Primitive& p, bool max);

// Projects a world point to screen pixels; false when behind the camera.
bool project(const glm::mat4& view_proj, const Rect& viewport, glm::vec3 world, ImVec2& out);

// Object-frame bounds: the mesh's, or the primitives' when there is no mesh.
void object_bounds(const EditorDocument& doc, int object, glm::vec3& lo, glm::vec3& hi);

// The object under a screen point (its projected bounds contain it; the nearest wins),
// or -1. Ghost copies of the limits preview are not picked.
int pick_object(const EditorDocument& doc, const UiState& ui, ImVec2 screen);

// Points the camera at the bounds of everything placed.
void frame_all(const EditorDocument& doc, UiState& ui);
// Points the camera at the selected object (everything when nothing is selected).
void frame_selected(const EditorDocument& doc, UiState& ui);

}  // namespace annex::authoring
