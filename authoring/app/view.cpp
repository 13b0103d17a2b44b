#include "view.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "annex/common/voter.h"

namespace annex::authoring {

Layout compute_layout(float width, float height, float menu_height) {
  const float left_w = std::clamp(width * 0.19f, 240.f, 320.f);
  const float right_w = std::clamp(width * 0.25f, 300.f, 420.f);
  const float body_h = height - menu_height;
  const float match_h = std::clamp(body_h * 0.33f, 160.f, 300.f);
  Layout l;
  l.outline = {0, menu_height, left_w, std::floor(body_h * 0.42f)};
  l.priorities = {0, menu_height + l.outline.h, left_w, body_h - l.outline.h};
  l.inspector = {width - right_w, menu_height, right_w, std::floor(body_h * 0.64f)};
  l.limits = {width - right_w, menu_height + l.inspector.h, right_w, body_h - l.inspector.h};
  const float mid_w = std::max(1.f, width - left_w - right_w);
  l.match = {left_w, height - match_h, mid_w, match_h};
  l.viewport = {left_w, menu_height, mid_w, std::max(1.f, body_h - match_h)};
  return l;
}

glm::vec3 camera_position(const Camera& c) {
  const float yaw = glm::radians(c.yaw_deg), pitch = glm::radians(c.pitch_deg);
  const glm::vec3 dir{std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                      std::cos(pitch) * std::cos(yaw)};
  return glm::vec3(c.target[0], c.target[1], c.target[2]) + dir * c.distance_m;
}

glm::mat4 view_matrix(const Camera& c) {
  return glm::lookAt(camera_position(c), glm::vec3(c.target[0], c.target[1], c.target[2]),
                     glm::vec3(0, 1, 0));
}

glm::mat4 projection_matrix(const Camera& c, float aspect) {
  const float near_m = std::max(0.002f, c.distance_m * 0.01f);
  return glm::perspective(glm::radians(c.fov_deg), std::max(aspect, 0.01f), near_m,
                          c.distance_m * 50.f + 10.f);
}

glm::mat4 to_mat4(const Pose& pose) {
  const glm::quat q(static_cast<float>(pose.rotation.w), static_cast<float>(pose.rotation.x),
                    static_cast<float>(pose.rotation.y), static_cast<float>(pose.rotation.z));
  glm::mat4 m = glm::mat4_cast(glm::normalize(q));
  m[3] = glm::vec4(static_cast<float>(pose.position.x), static_cast<float>(pose.position.y),
                   static_cast<float>(pose.position.z), 1.f);
  return m;
}

glm::mat4 primitive_matrix(const Primitive& p) {
  return to_mat4(p.pose);
}

glm::vec3 limit_scale(const Primitive& p, bool max) {
  auto s = [&](std::size_t i) {
    if (i >= p.dimensions.size()) return 1.f;
    return static_cast<float>(max ? p.dimensions[i].max_scale : p.dimensions[i].min_scale);
  };
  switch (p.kind) {
    case ShapeKind::sphere:
      return {s(0), s(0), s(0)};
    case ShapeKind::cylinder:
    case ShapeKind::cone:
    case ShapeKind::torus:
      return {s(0), s(0), s(1)};
    case ShapeKind::box:
      return {s(0), s(1), s(2)};
    case ShapeKind::plane:
      return {s(0), s(1), 1};
  }
  return {1, 1, 1};
}

void object_bounds(const EditorDocument& doc, int o, glm::vec3& lo, glm::vec3& hi) {
  if (const MeshData* m = doc.mesh_for(o)) {
    lo = {m->min.x, m->min.y, m->min.z};
    hi = {m->max.x, m->max.y, m->max.z};
    return;
  }
  lo = glm::vec3(-0.05f);
  hi = glm::vec3(0.05f);
  bool first = true;
  for (const Primitive& p : doc.spec().objects[o].primitives) {
    double r = 0;
    for (const Dimension& d : p.dimensions) r = std::max(r, d.value_m);
    const glm::vec3 c(p.pose.position.x, p.pose.position.y, p.pose.position.z);
    const glm::vec3 e(static_cast<float>(r));
    lo = first ? c - e : glm::min(lo, c - e);
    hi = first ? c + e : glm::max(hi, c + e);
    first = false;
  }
}

int pick_object(const EditorDocument& doc, const UiState& ui, ImVec2 screen) {
  const Rect& vp = ui.layout.viewport;
  const glm::mat4 view_proj = projection_matrix(ui.camera, vp.w / vp.h) * view_matrix(ui.camera);
  const glm::vec3 eye = camera_position(ui.camera);
  int best = -1;
  float best_distance = 1e30f;
  for (const Placement& p : place_objects(doc, ui)) {
    if (p.ghost) continue;
    glm::vec3 lo, hi;
    object_bounds(doc, p.object, lo, hi);
    ImVec2 smin(1e9f, 1e9f), smax(-1e9f, -1e9f);
    bool visible = true;
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
      ImVec2 s;
      if (!project(view_proj, vp, glm::vec3(p.model * glm::vec4(corner, 1.f)), s)) visible = false;
      smin = ImVec2(std::min(smin.x, s.x), std::min(smin.y, s.y));
      smax = ImVec2(std::max(smax.x, s.x), std::max(smax.y, s.y));
    }
    if (!visible || screen.x < smin.x || screen.x > smax.x || screen.y < smin.y ||
        screen.y > smax.y)
      continue;
    const float d = glm::length(glm::vec3(p.model * glm::vec4(0.5f * (lo + hi), 1.f)) - eye);
    if (d < best_distance) {
      best_distance = d;
      best = p.object;
    }
  }
  return best;
}

std::vector<Placement> place_objects(const EditorDocument& doc, const UiState& ui) {
  std::vector<Placement> out;
  const auto& objects = doc.spec().objects;
  const int sel = doc.selection().object;
  if (ui.limits_preview && sel >= 0 && sel < static_cast<int>(objects.size()) &&
      !objects[sel].primitives.empty()) {
    const VirtualObject& o = objects[sel];
    const Primitive& salient = o.primitives[primitive_priority_order(o)[0]];
    glm::vec3 lo, hi;
    object_bounds(doc, sel, lo, hi);
    const glm::mat4 frame = primitive_matrix(salient);
    const glm::mat4 inv = glm::inverse(frame);
    const glm::vec3 smin = limit_scale(salient, false), smax = limit_scale(salient, true);
    const float gap = 0.05f;
    const float w = hi.x - lo.x;
    const float big = std::max({smax.x, smax.y, smax.z, 1.f});
    const float small = std::max({smin.x, smin.y, smin.z});
    const float x_min = -(w * (1.f + small) * 0.5f + gap) - w * 0.1f;
    const float x_max = w * (1.f + big) * 0.5f + gap + w * 0.1f;
    auto scaled = [&](glm::vec3 s, float x) {
      const glm::mat4 about = frame * glm::scale(glm::mat4(1.f), s) * inv;
      // Scaled copies still stand on the floor where the object does.
      float bottom = 1e9f;
      for (int k = 0; k < 8; ++k) {
        const glm::vec3 corner((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
        bottom = std::min(bottom, glm::vec3(about * glm::vec4(corner, 1.f)).y);
      }
      const glm::vec3 shift(x - 0.5f * (lo.x + hi.x), lo.y - bottom, 0);
      return glm::translate(glm::mat4(1.f), shift) * about;
    };
    out.push_back({sel, scaled(smin, x_min), "min", true});
    out.push_back({sel, scaled(glm::vec3(1.f), 0.f), nullptr, false});
    out.push_back({sel, scaled(smax, x_max), "max", true});
    return out;
  }
  float cursor = 0;
  const float gap = 0.08f;
  for (int i = 0; i < static_cast<int>(objects.size()); ++i) {
    glm::vec3 lo, hi;
    object_bounds(doc, i, lo, hi);
    out.push_back(
        {i, glm::translate(glm::mat4(1.f), glm::vec3(cursor - lo.x, 0, 0)), nullptr, false});
    cursor += (hi.x - lo.x) + gap;
  }
  const float shift = -(cursor - gap) * 0.5f;
  for (Placement& p : out)
    p.model = glm::translate(glm::mat4(1.f), glm::vec3(shift, 0, 0)) * p.model;
  return out;
}

bool project(const glm::mat4& view_proj, const Rect& vp, glm::vec3 world, ImVec2& out) {
  const glm::vec4 c = view_proj * glm::vec4(world, 1.f);
  if (c.w <= 1e-6f) return false;
  const float x = c.x / c.w, y = c.y / c.w;
  out = ImVec2(vp.x + (x * 0.5f + 0.5f) * vp.w, vp.y + (1.f - (y * 0.5f + 0.5f)) * vp.h);
  return true;
}

namespace {

// Points the camera at the placed copies for which `keep` holds; false when none.
template <typename Keep>
bool frame_placements(const EditorDocument& doc, UiState& ui, Keep keep) {
  const std::vector<Placement> placed = place_objects(doc, ui);
  glm::vec3 lo(1e9f), hi(-1e9f);
  bool any = false;
  for (const Placement& p : placed) {
    if (!keep(p)) continue;
    any = true;
    glm::vec3 a, b;
    object_bounds(doc, p.object, a, b);
    for (int k = 0; k < 8; ++k) {
      const glm::vec3 corner((k & 1) ? b.x : a.x, (k & 2) ? b.y : a.y, (k & 4) ? b.z : a.z);
      const glm::vec3 w = glm::vec3(p.model * glm::vec4(corner, 1.f));
      lo = glm::min(lo, w);
      hi = glm::max(hi, w);
    }
  }
  if (!any) return false;
  const glm::vec3 c = 0.5f * (lo + hi);
  const float radius = std::max(0.05f, 0.5f * glm::length(hi - lo));
  ui.camera.target[0] = c.x;
  ui.camera.target[1] = c.y;
  ui.camera.target[2] = c.z;
  const float aspect = ui.layout.viewport.h > 0 ? ui.layout.viewport.w / ui.layout.viewport.h : 1.6f;
  const float half = glm::radians(ui.camera.fov_deg) * 0.5f * std::min(1.f, aspect);
  ui.camera.distance_m = radius / std::sin(half) * 1.2f;
  return true;
}

}  // namespace

void frame_all(const EditorDocument& doc, UiState& ui) {
  if (!frame_placements(doc, ui, [](const Placement&) { return true; })) ui.camera = Camera{};
}

void frame_selected(const EditorDocument& doc, UiState& ui) {
  const int object = doc.selection().object;
  if (object < 0 ||
      !frame_placements(doc, ui, [&](const Placement& p) { return p.object == object && !p.ghost; }))
    frame_all(doc, ui);
}

}  // namespace annex::authoring
