// ObjectShapeRecognizer: fits constrained by the support plane. Objects rest on the
// plane, so upright cylinders, cones, boxes and flat tori share its normal as axis and
// their bottom lies on it; a sphere's centre sits one radius above it. That turns 3D
// shape detection into small 2D fits (circles, rectangles, radius profiles) that are
// fast and robust on the half of an object a depth camera sees. The salient shape is
// the candidate with the best truncated-quadratic (MSAC) score over all points, with
// sanity bounds and a margin for the more complex shapes (docs/perception.md).
#include "annex/runtime/object_shape_recognizer.h"

#include "annex/runtime/frame.h"
#include "cylinder_any_axis.h"
#include "point_scatter.h"
#include "shape_rays.h"
#include "shape_residuals.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <optional>
#include <random>

namespace annex {
namespace {

constexpr double kPi = 3.14159265358979323846;

// sqrt(a^2 + b^2). std::hypot guards against overflow, which lengths in metres never
// need, at several times the cost (it was a sixth of the shape stage's time).
inline double len2(double a, double b) { return std::sqrt(a * a + b * b); }

// A point in plane coordinates: a, b along the plane, h height above it.
struct Local {
  double a = 0, b = 0, h = 0;
};

struct PlaneFrame {
  Vec3 n, u, v;
  double d = 0;
  Local to_local(Vec3 p) const { return {dot(u, p), dot(v, p), dot(n, p) + d}; }
  Vec3 to_world(double a, double b, double h) const { return u * a + v * b + n * (h - d); }
  Vec3 dir(double da, double db, double dh) const { return u * da + v * db + n * dh; }
};

PlaneFrame make_frame(const Plane& plane) {
  PlaneFrame f;
  f.n = normalized(plane.normal);
  f.d = plane.d / norm(plane.normal);
  const Vec3 seed = std::abs(f.n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  f.u = normalized(cross(f.n, seed));
  f.v = cross(f.n, f.u);
  return f;
}

struct Samples {
  std::vector<Local> p;
  std::vector<double> up;   // normal . up, or 0 when normals are unknown
  std::vector<double> na, nb;  // the normal's components along the plane axes
  std::vector<double> tol;  // per-point residual tolerance
  std::vector<Vec3> xyz;
  bool has_normals = false;
  double top = 0;  // object height above the plane
  // The height 90 % of the points lie under: a few of a neighbour's points (a ball's edge
  // beside a ring, given to the ring by a straight cut) leave it where the object's is.
  // The top's when ShapeRecognizerParams::torus_own_points is off.
  double bulk_top = 0;
  Local eye;       // the camera (the sensor's origin) in plane coordinates
  bool own_side_hides = true;  // ShapeRecognizerParams::own_side_hides
  DepthNoise noise;            // ShapeRecognizerParams::depth_noise
  // The support's surface seen around the object (SupportAround), with each point's
  // tolerance, and the image pixels each stands for.
  std::vector<Local> ground;
  std::vector<double> ground_tol;
  double ground_pixels = 1;
  int foot_points = 0;  // points within kFaceFootHeight of the plane
};

enum class Model { sphere, cylinder, cone, torus, box, lying_cylinder };

// Every candidate's parameters in plane coordinates.
struct Candidate {
  Model model = Model::cylinder;
  double ca = 0, cb = 0;  // axis (upright) or centre position on the plane
  double h0 = 0, h1 = 0;  // base and top heights of upright shapes
  double r0 = 0, r1 = 0;  // radius at base and top (cylinder: equal)
  double hc = 0;          // sphere / torus centre height
  double major = 0, minor = 0;
  double theta = 0;       // box / lying cylinder orientation in the plane
  double ex = 0, ey = 0;  // box half sizes; lying cylinder: ex = half length
  bool valid = false;
  bool as_cylinder = false;  // a frustum reported as the cylinder of its mean radius
  bool depth_unseen = false;  // a box seen by one side face alone, no top: depth not measured
  double floor_h = -1;       // an open container's inner floor height (cylinder, cone), -1 none
  double lid_h = -1;  // a cylinder's lid: its cap's median height (lid_spread_sigmas), -1 none
  double score = 0, coverage = 0, rms = 0;
  // The share of the score from points credited half (in_lid, in_rim_part), and the share
  // of the points explained within their tolerance (credited_rival).
  double credit = 0, explained = 0;
};

// A candidate's terms that do not depend on the point: computed once per pass over the
// points, not once per point (the same expressions, so the same values).
struct CandidateTerms {
  double cs = 1, sn = 0;           // box, lying cylinder: cos and sin of the azimuth
  double span = 1, cos_a = 1;      // cylinder, cone: height span, cos of the side's slope
};

CandidateTerms terms_of(const Candidate& c) {
  CandidateTerms t;
  switch (c.model) {
    case Model::cylinder:
    case Model::cone: {
      t.span = std::max(c.h1 - c.h0, 1e-6);
      const double slope = (c.r1 - c.r0) / t.span;
      t.cos_a = 1.0 / std::sqrt(1.0 + slope * slope);
      break;
    }
    case Model::box:
    case Model::lying_cylinder:
      t.cs = std::cos(c.theta);
      t.sn = std::sin(c.theta);
      break;
    default:
      break;
  }
  return t;
}

// Distance from a point to the visible surface of a solid resting on the plane.
double distance(const Candidate& c, const CandidateTerms& k, const Local& p) {
  const double da = p.a - c.ca, db = p.b - c.cb;
  switch (c.model) {
    case Model::sphere:
      return std::abs(std::sqrt(da * da + db * db + (p.h - c.hc) * (p.h - c.hc)) - c.r0);
    case Model::cylinder:
    case Model::cone: {
      const double rho = std::sqrt(da * da + db * db);
      const double t = std::clamp((p.h - c.h0) / k.span, 0.0, 1.0);
      const double r_at = c.r0 + (c.r1 - c.r0) * t;
      // Side: radial offset (scaled by the slope) plus any overshoot beyond the ends.
      const double over = p.h > c.h1 ? p.h - c.h1 : (p.h < c.h0 ? c.h0 - p.h : 0.0);
      const double side = len2((rho - r_at) * k.cos_a, over);
      const double cap = len2(std::max(0.0, rho - c.r1), p.h - c.h1);
      // An open container (a pot, a cup, a bowl) shows its inner floor through its top.
      const double floor = c.floor_h >= 0 && rho < r_at && p.h < c.h1 ? std::abs(p.h - c.floor_h) : 1e9;
      return std::min({side, cap, floor});
    }
    case Model::torus: {
      const double rho = std::sqrt(da * da + db * db);
      return std::abs(len2(rho - c.major, p.h - c.hc) - c.minor);
    }
    case Model::box: {
      const double x = std::abs(k.cs * da + k.sn * db), y = std::abs(-k.sn * da + k.cs * db);
      const double h_top = c.h1;
      const double ox = x - c.ex, oy = y - c.ey, oh = p.h - h_top;
      if (ox <= 0 && oy <= 0 && oh <= 0 && p.h >= 0) return std::min({-ox, -oy, -oh});
      return std::sqrt(std::pow(std::max(ox, 0.0), 2) + std::pow(std::max(oy, 0.0), 2) +
                       std::pow(std::max(oh, 0.0) + std::max(-p.h, 0.0), 2));
    }
    case Model::lying_cylinder: {
      const double s = k.cs * da + k.sn * db, w = -k.sn * da + k.cs * db;
      const double rho = len2(w, p.h - c.hc);
      const double over = std::max(std::abs(s) - c.ex, 0.0);
      const double side = len2(rho - c.r0, over);
      const double cap = len2(std::max(0.0, rho - c.r0), std::abs(s) - c.ex);
      return std::min(side, cap);
    }
  }
  return 1e9;
}

// The normal a box or a lying cylinder has at the surface point nearest p, in plane
// coordinates (a, b, up): a box's face's, a lying cylinder's radial direction or its cap's.
std::array<double, 3> model_normal(const Candidate& c, const CandidateTerms& k, const Local& p) {
  const double da = p.a - c.ca, db = p.b - c.cb;
  const double s = k.cs * da + k.sn * db, w = -k.sn * da + k.cs * db;
  auto plane_dir = [&](double along, double across, double up) {
    return std::array<double, 3>{k.cs * along - k.sn * across, k.sn * along + k.cs * across, up};
  };
  if (c.model == Model::box) {
    const double to_top = std::abs(p.h - c.h1), to_x = std::abs(std::abs(s) - c.ex),
                 to_y = std::abs(std::abs(w) - c.ey);
    if (to_top <= to_x && to_top <= to_y) return {0, 0, 1};
    return to_x <= to_y ? plane_dir(s < 0 ? -1 : 1, 0, 0) : plane_dir(0, w < 0 ? -1 : 1, 0);
  }
  const double dh = p.h - c.hc, rho = len2(w, dh);
  if (std::abs(std::abs(s) - c.ex) < std::abs(rho - c.r0) || rho <= 0)
    return plane_dir(s < 0 ? -1 : 1, 0, 0);
  return plane_dir(0, w / rho, dh / rho);
}

// A side's normal runs across a cylinder's axis, a cap's along it: points whose normal's
// share along the axis is below this are the side's (as cylinder_any_axis.cpp's).
constexpr double kSideNormalAlong = 0.4;

// Side normals bunched into faces 90 degrees apart give a flatness (|mean of 4x their
// angle|) near 1, normals sweeping round a curved side near 0; below this the sides are
// round (the upright test on a box's side normals).
constexpr double kRoundSides = 0.3;

// The same across a level axis: a lying cylinder shows the half of its round side that
// faces the camera, its normals smoothed over a neighbourhood that is a large share of
// its radius from a metre or two, so they bunch more than an upright side's (a dark tin
// lying 1.5 m away, rooms 13321: 0.33); a box's faces give 0.77 to 0.94 within 2 m
// (rooms 13001-13060). Between the two; nearer_than_box_faces decides the rest.
constexpr double kRoundAcrossAxis = 0.4;

// A cylinder or cone open at the top (a pot, a mug, a bowl): the camera sees its inner
// floor through the opening, up-facing points inside the side and well below the rim.
// When they are at least 5 % of the points and lie in the lower third (a floor is near
// the base), the solid gets that floor; a closed can shows no such points.
void settle_inner_floor(Candidate& c, const Samples& s) {
  if ((c.model != Model::cylinder && c.model != Model::cone) || !s.has_normals) return;
  const double span = c.h1 - c.h0;
  if (span <= 0) return;
  std::vector<double> h;
  for (size_t i = 0; i < s.p.size(); ++i) {
    const Local& p = s.p[i];
    if (s.up[i] < 0.8 || p.h > c.h1 - 3 * s.tol[i]) continue;
    const double t = std::clamp((p.h - c.h0) / span, 0.0, 1.0);
    const double r_at = c.r0 + (c.r1 - c.r0) * t;
    if (len2(p.a - c.ca, p.b - c.cb) < r_at - s.tol[i]) h.push_back(p.h);
  }
  if (h.size() < 0.05 * s.p.size()) return;
  std::nth_element(h.begin(), h.begin() + h.size() / 2, h.end());
  const double floor = h[h.size() / 2];
  if (floor < c.h0 + span / 3) c.floor_h = floor;
}

// A sphere is closed and convex: the camera sees only the half facing it, so a point on
// its far half (outward normal pointing away from the camera by more than the noise) is
// not a point of that sphere: it is the inside of a bowl, a cup or a pot, whose open top
// shows the far inner wall.
bool behind_sphere(const Candidate& c, const Local& p, const Local& eye, double tol) {
  if (c.model != Model::sphere) return false;
  const double ra = p.a - eye.a, rb = p.b - eye.b, rh = p.h - eye.h;  // the ray to p
  const double ray = std::sqrt(ra * ra + rb * rb + rh * rh);
  if (ray <= 0) return false;
  // Depth of p behind the sphere's silhouette plane (through its centre, across the ray).
  const double behind = ((p.a - c.ca) * ra + (p.b - c.cb) * rb + (p.h - c.hc) * rh) / ray;
  return behind > tol;
}

// The ray from the eye to p against candidate c's upright solid (cylinder, cone or box)
// shrunk by `side` at its sides and by `top` and `foot` at its ends, in the solid's own
// frame: centred, axis up, a frustum widening up mirrored so that it narrows to +z
// (shape_rays.h), its real top then the base. hit.t is infinite when the shrunk solid is
// empty or missed; `inside_foot`: p lies inside the shrunk solid's foot outline.
struct RayIntoSolid {
  shape_rays::LocalHit hit;
  double length = 0;  // from the eye to p
  bool mirrored = false;
  bool inside_foot = false;
};

RayIntoSolid ray_into_solid(const Candidate& c, const CandidateTerms& k, Local eye, Local p,
                            double side, double top, double foot) {
  RayIntoSolid r;
  const double lo = c.h0 + foot, hi = c.h1 - top, height = hi - lo, zc = 0.5 * (lo + hi);
  r.mirrored = c.model == Model::cone && c.r0 < c.r1;
  const auto local = [&](Local q) {
    const double da = q.a - c.ca, db = q.b - c.cb, z = r.mirrored ? zc - q.h : q.h - zc;
    return c.model == Model::box ? Vec3{k.cs * da + k.sn * db, -k.sn * da + k.cs * db, z}
                                 : Vec3{da, db, z};
  };
  const Vec3 o = local(eye), q = local(p), ray = q - o;
  r.length = norm(ray);
  if (height <= 0 || r.length <= 0) return r;
  const Vec3 d = ray * (1 / r.length);
  if (c.model == Model::box) {
    const double ex = c.ex - side, ey = c.ey - side;
    if (ex <= 0 || ey <= 0) return r;
    r.inside_foot = std::abs(q.x) < ex && std::abs(q.y) < ey;
    r.hit = shape_rays::hit_box(o, d, {ex, ey, 0.5 * height});
    return r;
  }
  // A slanted side moves in by the margin over the cosine of its slope.
  const double wide = std::max(c.r0, c.r1), narrow = std::min(c.r0, c.r1), in = side / k.cos_a;
  if (wide <= in) return r;
  r.inside_foot = len2(q.x, q.y) < c.r0 - in;
  r.hit = c.model == Model::cylinder
              ? shape_rays::hit_cylinder(o, d, wide - in, height)
              : shape_rays::hit_cone(o, d, wide - in, height, std::max(0.0, narrow - in));
  return r;
}

// A closed solid hides its own far side: a point that the ray from the eye reaches only
// through an upright cylinder's or cone's side (the solid shrunk by the point's
// tolerance, which the fit and the noise leave unsure) is no point of that solid
// (ShapeRecognizerParams::own_side_hides). Through its top it may be one: the far inner
// wall of an open cup, pot or bowl seen over its rim. Boxes are not asked: a box fitted
// to one face has its depth unseen, and the real nyu_basement frame's bags in an open
// carton, one partial box, were then cut into two whole props.
bool hidden_by_own_side(const Candidate& c, const CandidateTerms& k, const Local& p,
                        const Local& eye, double tol) {
  if (c.model != Model::cylinder && c.model != Model::cone) return false;
  const RayIntoSolid r = ray_into_solid(c, k, eye, p, tol, tol, tol);
  // Through its side or base, not its top.
  return r.hit.t < r.length && r.hit.normal.z * (r.mirrored ? -1.0 : 1.0) < 0.5;
}

// Inside the upper third of a box or cylinder: where lids, gables and caps sit.
bool in_lid(const Candidate& c, const CandidateTerms& k, const Local& p) {
  if (c.model != Model::box && c.model != Model::cylinder) return false;
  if (p.h > c.h1 || p.h < c.h0 + 0.67 * (c.h1 - c.h0)) return false;
  const double da = p.a - c.ca, db = p.b - c.cb;
  if (c.model == Model::cylinder) return da * da + db * db < c.r0 * c.r0;
  return std::abs(k.cs * da + k.sn * db) < c.ex && std::abs(-k.sn * da + k.cs * db) < c.ey;
}

// Just outside the side of an upright cylinder, in the upper half of its body: where a
// container's rim lip and handles sit (a pot, a mug). They stand out of the body by a
// few millimetres (a lip) to a third of its radius (a handle) and are attached at the
// rim, so they are parts of it, not evidence against it; a box's corners, which a
// cylinder through its sides also leaves out, run down to its base. Not for cones: a
// cone's narrowing top would take a jug's handle as such a part and beat the cylinder.
bool in_rim_part(const Candidate& c, const Local& p, double tol) {
  if (c.model != Model::cylinder) return false;
  const double span = c.h1 - c.h0;
  if (span <= 0 || p.h < c.h0 + 0.5 * span || p.h > c.h1 + tol) return false;
  const double t = std::clamp((p.h - c.h0) / span, 0.0, 1.0);
  const double r_at = c.r0 + (c.r1 - c.r0) * t;
  const double rho = len2(p.a - c.ca, p.b - c.cb);
  return rho > r_at && rho < r_at + tol + 0.35 * std::max(c.r0, c.r1);
}

// MSAC-style score (1 - (d/tol)^2 per explained point) and coverage. Points inside a
// box's or cylinder's lid region count half: a carton's gable or a bottle's cap is
// not the flat top the solid assumes, yet it is no evidence against the solid. So do a
// container's rim lip and handles (in_rim_part).
// Sides and tops are averaged with equal weight when both are seen: a wide, low box's
// top is a cylinder's cap too, and only its flat sides tell them apart.
void evaluate(Candidate& c, const Samples& s) {
  double score[2] = {0, 0}, covered[2] = {0, 0}, count[2] = {0, 0}, credited[2] = {0, 0}, sq = 0;
  int explained = 0;
  const CandidateTerms terms = terms_of(c);
  for (size_t i = 0; i < s.p.size(); ++i) {
    const int g = s.has_normals && std::abs(s.up[i]) > 0.6 ? 1 : 0;
    count[g] += 1;
    const double d = distance(c, terms, s.p[i]);
    const double e = d / s.tol[i];
    if (e < 1 && !behind_sphere(c, s.p[i], s.eye, s.tol[i]) &&
        !(s.own_side_hides && hidden_by_own_side(c, terms, s.p[i], s.eye, s.tol[i]))) {
      score[g] += 1 - e * e;
      sq += d * d;
      covered[g] += 1;
      ++explained;
    } else if (in_lid(c, terms, s.p[i]) || in_rim_part(c, s.p[i], s.tol[i])) {
      score[g] += 0.5;
      covered[g] += 0.5;
      credited[g] += 0.5;
    }
  }
  const double n = std::max<size_t>(s.p.size(), 1);
  if (count[0] >= 0.1 * n && count[1] >= 0.1 * n) {
    c.score = 0.5 * (score[0] / count[0] + score[1] / count[1]);
    c.coverage = 0.5 * (covered[0] / count[0] + covered[1] / count[1]);
    c.credit = 0.5 * (credited[0] / count[0] + credited[1] / count[1]);
  } else {
    c.score = (score[0] + score[1]) / n;
    c.coverage = (covered[0] + covered[1]) / n;
    c.credit = (credited[0] + credited[1]) / n;
  }
  c.rms = explained > 0 ? std::sqrt(sq / explained) : 0;
  c.explained = explained / n;
}

// A frustum (both radii non-zero: a cup, a bowl, a lampshade) is reported as itself, a
// cone with its narrow end's radius, when it explains its points better than the
// cylinder of its mean radius by `margin`; otherwise as that cylinder (a jug whose
// sides barely taper reads as a cylinder).
void settle_frustum(Candidate& c, const Samples& s, double margin) {
  if (c.model != Model::cone || std::min(c.r0, c.r1) <= 0) return;
  Candidate cyl = c;
  cyl.model = Model::cylinder;
  cyl.r0 = cyl.r1 = (c.r0 + c.r1) / 2;
  evaluate(cyl, s);
  c.as_cylinder = cyl.score > c.score - margin;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}

// The LM stops once a step is this small (see refine_lm).
constexpr double kLmConvergedStep = 1e-7;

// Levenberg-Marquardt on a few parameters with Huber weights. `residual(params, i, g)`
// gives point i's signed residual and, when `g` is not null, its gradient in `g`.
template <int N, typename F>
void refine_lm(std::array<double, N>& x, int count, const std::vector<double>& scale, F residual,
               int iterations) {
  using Gradient = Eigen::Matrix<double, N, 1>;
  using Normal = Eigen::Matrix<double, N, N>;
  if (count < N + 1) return;
  double lambda = 1e-3;
  // The Huber cost at p and, when `jtj` is not null, the weighted normal equations there
  // (one pass: a step taken needs both at its new point).
  auto evaluate = [&](const std::array<double, N>& p, Normal* jtj, Gradient* jtr) {
    double c = 0;
    if (jtj) {
      jtj->setZero();
      jtr->setZero();
    }
    for (int i = 0; i < count; ++i) {
      Gradient g;
      const double r = residual(p, i, jtj ? &g : static_cast<Gradient*>(nullptr)), k = 2.0 * scale[i];
      c += std::abs(r) < k ? r * r : 2 * k * std::abs(r) - k * k;
      if (!jtj) continue;
      const double w = std::abs(r) < k ? 1.0 : k / std::abs(r);
      *jtj += w * g * g.transpose();
      *jtr += w * g * r;
    }
    return c;
  };
  Normal jtj, next_jtj;
  Gradient jtr, next_jtr;
  double current = evaluate(x, &jtj, &jtr);
  for (int it = 0; it < iterations; ++it) {
    const bool last = it + 1 == iterations;
    bool improved = false;
    for (int attempt = 0; attempt < 6 && !improved; ++attempt) {
      Normal a = jtj;
      for (int j = 0; j < N; ++j) a(j, j) += lambda * (jtj(j, j) + 1e-12);
      const Gradient delta = a.ldlt().solve(-jtr);
      std::array<double, N> next = x;
      for (int j = 0; j < N; ++j) next[j] += delta[j];
      // Converged: an undamped step below kLmConvergedStep of every parameter's scale
      // (metres or radians: a tenth of a micrometre against the tenths of millimetres the
      // shapes are reported in) moves nothing a caller sees, and the iterations left
      // would repeat it. (A large lambda shortens steps that have not converged.)
      bool negligible = attempt == 0 && lambda < 0.1;
      for (int j = 0; j < N && negligible; ++j)
        negligible = std::abs(delta[j]) <= kLmConvergedStep * std::max(1.0, std::abs(x[j]));
      if (negligible) {
        x = next;
        return;
      }
      // The first try is usually taken: its normal equations come with its cost.
      const bool with_normal = attempt == 0 && !last;
      const double c = evaluate(next, with_normal ? &next_jtj : nullptr, &next_jtr);
      if (std::isfinite(c) && c < current) {
        x = next;
        current = c;
        lambda = std::max(lambda * 0.3, 1e-7);
        improved = true;
        if (with_normal) {
          jtj = next_jtj;
          jtr = next_jtr;
        } else if (!last) {
          evaluate(x, &jtj, &jtr);
        }
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;
  }
}

// refine_lm with the residual's own analytic gradient.
template <int N, typename F>
void refine_analytic(std::array<double, N>& x, int count, const std::vector<double>& scale,
                     F residual, int iterations = 8) {
  refine_lm<N>(x, count, scale, residual, iterations);
}

// refine_analytic first on every k-th point (at most `sample`, even over the points'
// order), then two iterations on all points from there: the iterations from the start,
// far from the minimum, run on the sample; the last ones, which set the result, on all
// points. Objects with at most twice `sample` points get 8 iterations on all of them.
template <int N, typename F>
void refine_sampled(std::array<double, N>& x, int count, const std::vector<double>& scale, F residual,
                    int sample) {
  if (sample > 0 && count > 2 * sample) {
    const int step = (count + sample - 1) / sample;
    std::vector<int> pick;
    std::vector<double> pick_scale;
    for (int i = 0; i < count; i += step) {
      pick.push_back(i);
      pick_scale.push_back(scale[static_cast<size_t>(i)]);
    }
    refine_analytic<N>(x, static_cast<int>(pick.size()), pick_scale,
                       [&](const std::array<double, N>& p, int j, Eigen::Matrix<double, N, 1>* g) {
                         return residual(p, pick[static_cast<size_t>(j)], g);
                       });
    refine_analytic<N>(x, count, scale, residual, 2);
    return;
  }
  refine_analytic<N>(x, count, scale, residual);
}

struct Circle {
  double x = 0, y = 0, r = 0;
  bool ok = false;
};

// Algebraic (Kasa) circle through weighted 2D points: a starting point for refine().
Circle kasa_circle(const std::vector<std::array<double, 2>>& q) {
  if (q.size() < 3) return {};
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const auto& p : q) {
    const Eigen::Vector3d row(p[0], p[1], 1.0);
    a += row * row.transpose();
    b += row * (p[0] * p[0] + p[1] * p[1]);
  }
  const Eigen::Vector3d s = a.ldlt().solve(b);
  const double cx = s[0] / 2, cy = s[1] / 2, r2 = s[2] + cx * cx + cy * cy;
  if (!std::isfinite(r2) || r2 <= 0) return {};
  return {cx, cy, std::sqrt(r2), true};
}

Circle circle_through(const std::array<double, 2>& p1, const std::array<double, 2>& p2,
                      const std::array<double, 2>& p3) {
  const double ax = p2[0] - p1[0], ay = p2[1] - p1[1], bx = p3[0] - p1[0], by = p3[1] - p1[1];
  const double det = 2 * (ax * by - ay * bx);
  if (std::abs(det) < 1e-12) return {};
  const double a2 = ax * ax + ay * ay, b2 = bx * bx + by * by;
  const double ux = (by * a2 - ay * b2) / det, uy = (ax * b2 - bx * a2) / det;
  return {p1[0] + ux, p1[1] + uy, len2(ux, uy), true};
}

// Every third point of a circle fit, kept in arrays of their own: each circle's
// residuals are one packed pass (Eigen's sqrt and division per element, the same values
// as len2). `width` is each point's: its tolerance, or less (robust_circle).
struct CirclePoints {
  Eigen::ArrayXd a, b, width;
  mutable Eigen::ArrayXd e;  // scratch for each circle's residuals

  CirclePoints(const std::vector<std::array<double, 2>>& q, const std::vector<double>& tol) {
    const Eigen::Index n = static_cast<Eigen::Index>((q.size() + 2) / 3);
    a.resize(n);
    b.resize(n);
    width.resize(n);
    e.resize(n);
    for (Eigen::Index j = 0; j < n; ++j) {
      a[j] = q[static_cast<size_t>(3 * j)][0];
      b[j] = q[static_cast<size_t>(3 * j)][1];
      width[j] = tol[static_cast<size_t>(3 * j)];
    }
  }

  // Each point within its width adds 1 - (residual / width)^2: packed (0 outside, adding
  // +0 leaves the sum as it is), then summed one at a time in the points' order.
  double score(const Circle& c) const {
    e = (((a - c.x).square() + (b - c.y).square()).sqrt() - c.r) / width;
    e = (e.abs() < 1).select(1 - e.square(), 0.0);
    double sum = 0;
    for (Eigen::Index j = 0; j < e.size(); ++j) sum += e[j];
    return sum;
  }

  // The median of the absolute residuals about `c`: quantile()'s (the upper of two
  // middles), selected in place.
  double median_residual(const Circle& c) const {
    e = (((a - c.x).square() + (b - c.y).square()).sqrt() - c.r).abs();
    if (e.size() == 0) return 0;
    double* mid = e.data() + e.size() / 2;
    std::nth_element(e.data(), mid, e.data() + e.size());
    return *mid;
  }
};

// The least scatter points are credited with: points laid exactly on a circle (a
// scatter of zero) would leave its consensus no width for rounding.
constexpr double kCircleLeastScatterM = 0.0005;

// The points' own scatter about their circle: the least median absolute residual among
// `circles`, as a sigma (Rousseeuw's least-median-of-squares scale: 1.4826 times it, and
// 1 + 5 / (n - 3) for the n points' few: the least of many medians runs low).
double least_median_scatter(const CirclePoints& pts, const std::vector<Circle>& circles) {
  double least = std::numeric_limits<double>::infinity();
  for (const Circle& c : circles) least = std::min(least, pts.median_residual(c));
  const double n = static_cast<double>(pts.a.size());
  return std::max(kCircleLeastScatterM, 1.4826 * (1 + 5 / std::max(1.0, n - 3)) * least);
}

// RANSAC circle (seeded; the algebraic circle through all points drawn too) followed by
// a geometric refinement on its inliers; handles, caps and neighbours' stray points are
// outliers. With ShapeRecognizerParams::circle_own_scatter each point's width is at most
// noise_factor times the points' own scatter (least_median_scatter), and the inliers are
// chosen again about the refined circle and refined once more.
Circle robust_circle(const std::vector<std::array<double, 2>>& q, const std::vector<double>& tol,
                     const ShapeRecognizerParams& params, std::mt19937_64& rng) {
  if (q.size() < 8) return {};
  std::uniform_int_distribution<size_t> pick(0, q.size() - 1);
  const auto sane = [&](const Circle& c) {
    return c.ok && c.r >= params.min_radius_m && c.r <= params.max_radius_m;
  };
  std::vector<Circle> drawn;
  for (int it = 0; it < 60; ++it) {
    const Circle c = circle_through(q[pick(rng)], q[pick(rng)], q[pick(rng)]);
    if (sane(c)) drawn.push_back(c);
  }
  const Circle k = kasa_circle(q);
  if (k.ok && k.r > params.min_radius_m && k.r < params.max_radius_m) drawn.push_back(k);
  if (drawn.empty()) return {};
  CirclePoints pts(q, tol);
  // Each point's width: its tolerance, at most `most`.
  double most = std::numeric_limits<double>::infinity();
  if (params.circle_own_scatter) {
    most = params.noise_factor * least_median_scatter(pts, drawn);
    pts.width = pts.width.min(most);
  }
  Circle best;
  double best_score = -1;
  for (const Circle& c : drawn) {
    const double score = pts.score(c);
    if (score > best_score) {
      best_score = score;
      best = c;
    }
  }
  std::array<double, 3> x{best.x, best.y, best.r};
  std::vector<std::array<double, 2>> in;
  std::vector<double> in_width;
  for (int round = 0; round < (params.circle_own_scatter ? 2 : 1); ++round) {
    in.clear();
    in_width.clear();
    for (size_t i = 0; i < q.size(); ++i) {
      const double width = std::min(tol[i], most);
      if (std::abs(len2(q[i][0] - x[0], q[i][1] - x[1]) - std::abs(x[2])) < 2.5 * width) {
        in.push_back(q[i]);
        in_width.push_back(width);
      }
    }
    refine_analytic<3>(x, static_cast<int>(in.size()), in_width,
                       [&](const std::array<double, 3>& p, int i, shape_residuals::Gradient<3>* g) {
                         return shape_residuals::circle(p, in[i][0], in[i][1], g);
                       });
  }
  return {x[0], x[1], std::abs(x[2]), true};
}

// Upright cylinder: circle of the side points' footprint; height from the plane (or
// `base`) to where the side stops fitting or the cap lies.
// How much better a circle explains an outline than a rectangle does: both refined on
// the outline (per 5-degree direction from the points' middle, the farthest point;
// Huber weights; tolerance the points' own or two pixels: where depth ends, a silhouette
// is off by about a pixel). Returns the rectangle's residual energy over the circle's
// (each residual capped at three tolerances): well above 1 for a round outline, at most
// about 1 for a rectangle's. `circle` gets the circle. 0 when the outline is not seen
// round most directions. `rect` starts the rectangle (a, b, azimuth, half sides); a
// negative half side asks for the outline's own minimum-area rectangle.
// A disc on its rim must be round by this much: the circle leaves half the rectangle's energy.
constexpr double kRoundOverRectangle = 2;
double outline_round_over_rectangle(const std::vector<std::array<double, 2>>& pts,
                                    const std::vector<double>& pt_tol, const std::vector<double>& depth,
                                    std::array<double, 5> rect, const ShapeRecognizerParams& params,
                                    Circle& circle) {
  constexpr int kBins = 72;
  if (pts.empty()) return 0;
  double ma = 0, mb = 0;
  for (const auto& p : pts) {
    ma += p[0];
    mb += p[1];
  }
  ma /= static_cast<double>(pts.size());
  mb /= static_cast<double>(pts.size());
  std::vector<int> far(kBins, -1);
  std::vector<double> far_r(kBins, 0);
  for (size_t i = 0; i < pts.size(); ++i) {
    const double da = pts[i][0] - ma, db = pts[i][1] - mb, r = len2(da, db);
    const int b = std::clamp(static_cast<int>((std::atan2(db, da) + kPi) / (2 * kPi) * kBins), 0, kBins - 1);
    if (r > far_r[b]) {
      far_r[b] = r;
      far[b] = static_cast<int>(i);
    }
  }
  std::vector<std::array<double, 2>> rim;
  std::vector<double> tol;
  for (int b = 0; b < kBins; ++b)
    if (far[b] >= 0) {
      rim.push_back(pts[far[b]]);
      tol.push_back(std::max(pt_tol[far[b]], 2 * std::abs(depth[far[b]]) / params.focal_px));
    }
  if (rim.size() < 0.75 * kBins) return 0;
  const Circle start = kasa_circle(rim);
  if (!start.ok) return 0;
  const int n = static_cast<int>(rim.size());
  std::array<double, 3> c{start.x, start.y, start.r};
  auto circle_residual = [&](const std::array<double, 3>& p, int i,
                             shape_residuals::Gradient<3>* g = nullptr) {
    return shape_residuals::circle(p, rim[i][0], rim[i][1], g);
  };
  refine_analytic<3>(c, n, tol, circle_residual);
  if (rect[3] < 0) {
    // The smallest-area rectangle over the outline's azimuths, 3 degrees apart.
    double best_area = std::numeric_limits<double>::max();
    for (int k = 0; k < 30; ++k) {
      const double th = k * kPi / 60, cs = std::cos(th), sn = std::sin(th);
      double u0 = 1e9, u1 = -1e9, v0 = 1e9, v1 = -1e9;
      for (const auto& q : rim) {
        const double u = cs * q[0] + sn * q[1], v = -sn * q[0] + cs * q[1];
        u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
      }
      if ((u1 - u0) * (v1 - v0) < best_area) {
        best_area = (u1 - u0) * (v1 - v0);
        const double uc = (u0 + u1) / 2, vc = (v0 + v1) / 2;
        rect = {cs * uc - sn * vc, sn * uc + cs * vc, th, (u1 - u0) / 2, (v1 - v0) / 2};
      }
    }
  }
  auto rectangle_residual = [&](const std::array<double, 5>& p, int i,
                                shape_residuals::Gradient<5>* g = nullptr) {
    return shape_residuals::rectangle(p, rim[i][0], rim[i][1], g);
  };
  refine_analytic<5>(rect, n, tol, rectangle_residual);
  double e_circle = 0, e_rectangle = 0;
  for (int i = 0; i < n; ++i) {
    const double cap = 9 * tol[i] * tol[i];
    e_circle += std::min(cap, std::pow(circle_residual(c, i), 2));
    e_rectangle += std::min(cap, std::pow(rectangle_residual(rect, i), 2));
  }
  circle = {c[0], c[1], std::abs(c[2]), true};
  if (circle.r < params.min_radius_m || circle.r > params.max_radius_m) return 0;
  return e_rectangle / std::max(e_circle, 1e-12);
}

// The footprint's outline seen from above against the box's rectangle: well above 1
// for a round top or rim (a can, a bowl, a lampshade seen from above).
double footprint_round_over_rectangle(const Samples& s, const Candidate& box,
                                      const ShapeRecognizerParams& params, Circle& circle) {
  std::vector<std::array<double, 2>> ab(s.p.size());
  std::vector<double> z(s.p.size());
  for (size_t i = 0; i < s.p.size(); ++i) {
    ab[i] = {s.p[i].a, s.p[i].b};
    z[i] = s.xyz[i].z;
  }
  return outline_round_over_rectangle(ab, s.tol, z, {box.ca, box.cb, box.theta, box.ex, box.ey},
                                      params, circle);
}

// A disc on its rim (lid to the camera) against a box's face: the outline seen along
// the disc's axis must be round, not a rectangle. Far away the tolerance grows until
// most of a rectangle's outline lies within it of a circle (nyu_basement's stacked bins,
// 3.5 m away); the energies still tell them apart.
double disc_round_over_rectangle(const Samples& s, Vec3 axis, const ShapeRecognizerParams& params) {
  const Vec3 seed = std::abs(axis.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = normalized(cross(axis, seed)), e2 = cross(axis, e1);
  std::vector<std::array<double, 2>> q(s.xyz.size());
  std::vector<double> z(s.xyz.size());
  for (size_t i = 0; i < s.xyz.size(); ++i) {
    q[i] = {dot(s.xyz[i], e1), dot(s.xyz[i], e2)};
    z[i] = s.xyz[i].z;
  }
  Circle unused;
  return outline_round_over_rectangle(q, s.tol, z, {0, 0, 0, -1, -1}, params, unused);
}

// The depth noise's spread in a point's height: sigma_z along its ray, times the ray's
// slope against the plane (the eye's height over the point's, over their distance).
double height_sigma(const Samples& s, int i) {
  const Local& q = s.p[static_cast<size_t>(i)];
  const double da = s.eye.a - q.a, db = s.eye.b - q.b, dh = s.eye.h - q.h;
  const double run = std::sqrt(da * da + db * db + dh * dh);
  return run > 0 ? s.noise.sigma_z(std::abs(s.xyz[static_cast<size_t>(i)].z)) * std::abs(dh) / run
                 : 0;
}

// A lid or an open top spans its cylinder's disc; a cap whose points (90 % of them) lie
// within this share of the radius of the axis is a small disc (fit_cylinder).
constexpr double kCapLeastSpread = 0.5;

// The footprint (a, b) of the points of `subset` that face sideways (their normals
// within about 45 degrees of level, when known) at heights lo to hi, with their
// tolerances: what an upright circle is fitted on.
struct Footprint {
  std::vector<std::array<double, 2>> q;
  std::vector<double> tol;
};
Footprint side_footprint(const Samples& s, const std::vector<int>& subset, double lo, double hi) {
  Footprint f;
  for (int i : subset) {
    if (s.has_normals && std::abs(s.up[i]) > 0.7) continue;
    if (s.p[i].h < lo || s.p[i].h > hi) continue;
    f.q.push_back({s.p[i].a, s.p[i].b});
    f.tol.push_back(s.tol[i]);
  }
  return f;
}

// The height `share` of the way from `base` up to `subset`'s top (its 99 % height).
double height_share(const Samples& s, const std::vector<int>& subset, double base, double share) {
  std::vector<double> heights;
  for (int i : subset) heights.push_back(s.p[i].h);
  return base + share * (quantile(heights, 0.99) - base);
}

Candidate fit_cylinder(const Samples& s, const std::vector<int>& subset, double base,
                       const ShapeRecognizerParams& params, std::mt19937_64& rng) {
  Candidate c;
  c.model = Model::cylinder;
  constexpr double kAll = std::numeric_limits<double>::infinity();
  // The body's circle comes from its lower part when that is seen well enough: a
  // bottle's shoulder and neck, higher up, are narrower and would shrink it.
  Footprint f = side_footprint(s, subset, -kAll, height_share(s, subset, base, 0.6));
  if (f.q.size() < 40) f = side_footprint(s, subset, -kAll, kAll);
  std::vector<std::array<double, 2>>& q = f.q;
  std::vector<double>& tol = f.tol;
  if (q.size() < 12) {
    q.clear();
    tol.clear();
    for (int i : subset) {
      q.push_back({s.p[i].a, s.p[i].b});
      tol.push_back(s.tol[i]);
    }
  }
  const Circle circle = robust_circle(q, tol, params, rng);
  if (!circle.ok) return c;
  c.ca = circle.x;
  c.cb = circle.y;
  c.r0 = c.r1 = circle.r;
  c.h0 = base;
  // Top: highest side inliers or the cap (points inside the circle facing up). A cap
  // high above the side (by two tolerances) on a small disc about the axis is a bottle's
  // on its neck, no top of its body.
  std::vector<double> side_h, cap_h, cap_sigma, cap_rho, cap_tol, all_h;
  for (int i : subset) {
    const double rho = len2(s.p[i].a - c.ca, s.p[i].b - c.cb);
    all_h.push_back(s.p[i].h);
    if (std::abs(rho - c.r0) < s.tol[i]) side_h.push_back(s.p[i].h);
    if (rho < c.r0 - s.tol[i] && (!s.has_normals || s.up[i] > 0.8)) {
      cap_h.push_back(s.p[i].h);
      cap_sigma.push_back(height_sigma(s, i));
      cap_rho.push_back(rho);
      cap_tol.push_back(s.tol[i]);
    }
  }
  double top = side_h.size() > 5 ? quantile(side_h, 0.98) : quantile(all_h, 0.98);
  const auto neck_cap = [&] {
    return quantile(cap_rho, 0.9) < kCapLeastSpread * c.r0 &&
           quantile(cap_h, 0.5) > top + 2 * quantile(cap_tol, 0.5);
  };
  if (cap_h.size() > 10 && !neck_cap()) {
    const double cap = quantile(cap_h, 0.5);
    top = std::max(top, cap);
    // A lid (its cap above the side's middle, not an open container's inner floor, and
    // flat to the noise, not bags in a box) seen from above sets the height, as a box's
    // top face does: the side's highest points include the rim's, which the depth noise
    // spreads above it (2 sigma at the 98 %).
    if (params.lid_spread_sigmas > 0 && side_h.size() > 5 && cap >= quantile(side_h, 0.5) &&
        quantile(cap_h, 0.75) - quantile(cap_h, 0.25) <=
            params.lid_spread_sigmas * quantile(cap_sigma, 0.5))
      top = c.lid_h = cap;
  }
  c.h1 = top;
  c.valid = c.h1 - c.h0 > 0.005 && c.r0 >= params.min_radius_m && c.r0 <= params.max_radius_m;
  return c;
}

// The cone of parameters x (axis a, b; radius at base and top) over span_ref's heights:
// valid when it narrows (or widens) clearly: by min_cone_taper of its wide radius, or
// short of it by no more than cone_taper_doubt standard errors of the measured narrowing
// (taper_error(), asked only then): a frustum as tapered as that measures, through the
// noise, as often under it as over it.
// With `to_apex`, a side narrowing to a small top runs on to its apex.
template <typename TaperError>
Candidate cone_from_parameters(const Candidate& span_ref, const std::array<double, 4>& x,
                               const ShapeRecognizerParams& params, TaperError taper_error,
                               bool to_apex = true) {
  Candidate c = span_ref;
  c.ca = x[0];
  c.cb = x[1];
  c.r0 = std::max(0.0, x[2]);
  c.r1 = std::max(0.0, x[3]);
  // The tip of a cone is too thin to see: when the side narrows to a small top,
  // extend it to the apex where the fitted radius reaches zero.
  if (to_apex && c.r1 < 0.35 * c.r0 && c.r0 > c.r1) {
    c.h1 = c.h0 + (c.h1 - c.h0) * c.r0 / (c.r0 - c.r1);
    c.r1 = 0;
  }
  const double wide = std::max(c.r0, c.r1), narrow = std::min(c.r0, c.r1);
  c.valid = wide >= params.min_radius_m && wide <= params.max_radius_m && wide - narrow > 0.008 &&
            (wide - narrow >= params.min_cone_taper * wide ||
             wide - narrow >= params.min_cone_taper * wide - params.cone_taper_doubt * taper_error());
  return c;
}

// The standard error of a cone's narrowing (radius at the top less radius at the base)
// fitted over the side points idx, their heights normalised by span: the slope of a
// straight line through radius against height, sigma_z / sqrt(n var(t)). The scanner
// smooths each point over its neighbours within shared_noise_radius_m, so points that
// close share their noise: n counts each side point one over the number of side points
// in its neighbourhood (as independent_points does), each of sigma_z at its depth. The
// count is estimated on an even sample of at most kTaperSample points against as many
// (a few thousand distances, not the side's square).
double taper_error(const Samples& s, const std::vector<int>& idx, double h0, double span,
                   double focal_px) {
  constexpr size_t kTaperSample = 64;
  if (idx.size() < 3) return 0;
  const size_t stride = std::max<size_t>(1, idx.size() / kTaperSample);
  double share = 0, var_z = 0, st = 0, stt = 0;
  size_t sampled = 0;
  for (size_t i = 0; i < idx.size(); ++i) {
    const Vec3& p = s.xyz[idx[i]];
    const double z = std::abs(p.z), sz = s.noise.sigma_z(z), t = (s.p[idx[i]].h - h0) / span;
    var_z += sz * sz;
    st += t;
    stt += t * t;
    if (i % stride != 0) continue;
    const double r = shared_noise_radius_m(z, focal_px, s.noise);
    size_t near = 0;
    for (size_t j = 0; j < idx.size(); j += stride) {  // i itself among them
      const Vec3 d = s.xyz[idx[j]] - p;
      near += dot(d, d) < r * r;
    }
    share += 1.0 / static_cast<double>(std::max<size_t>(near * stride, 1));
    ++sampled;
  }
  const double m = static_cast<double>(idx.size());
  const double n = share * m / static_cast<double>(std::max<size_t>(sampled, 1));
  const double var_t = std::max(stt / m - (st / m) * (st / m), 1e-12);
  return std::sqrt(var_z / m / (std::max(n, 1.0) * var_t));
}

// Whether a fitted cone is wider than its points: its widest section seen (a bowl's
// rim, a cone's foot where the height band starts) is part of what the camera sees of a
// solid standing on the plane, so some of its points lie that far from the axis. Wider
// by more than the tolerance, the fit converged away from the points (it explains a
// side by a far larger cone's arc).
bool cone_wider_than_its_points(const Samples& s, const std::vector<int>& subset, const Candidate& c) {
  if (subset.empty()) return false;
  std::vector<double> rho, tol, h;
  rho.reserve(subset.size());
  tol.reserve(subset.size());
  h.reserve(subset.size());
  for (int i : subset) {
    rho.push_back(len2(s.p[i].a - c.ca, s.p[i].b - c.cb));
    tol.push_back(s.tol[i]);
    h.push_back(s.p[i].h);
  }
  const double span = std::max(c.h1 - c.h0, 1e-6);
  auto radius_at = [&](double z) { return c.r0 + (c.r1 - c.r0) * std::clamp((z - c.h0) / span, 0.0, 1.0); };
  const double widest_seen = std::max(radius_at(quantile(h, 0.01)), radius_at(quantile(h, 0.99)));
  return widest_seen > quantile(rho, 0.99) + 2 * quantile(tol, 0.5);
}

// A second start for the cone fit: the axis through the centre of the footprint's
// outline (seen from above, per 5-degree direction from the points' middle the farthest
// point: the rim of a bowl, the base of a cone apex up), the radii from the side's
// profile about that axis (a straight line through radius against height). False when
// the outline is not seen round most directions.
// The circle through the footprint's outline seen from above: per 5-degree direction
// from the points' middle the farthest point, a circle through them (not ok when the
// outline is not seen most of the way round).
Circle footprint_circle(const Samples& s, const std::vector<int>& subset) {
  constexpr int kBins = 72;
  if (subset.empty()) return {};
  double ma = 0, mb = 0;
  for (int i : subset) {
    ma += s.p[i].a;
    mb += s.p[i].b;
  }
  ma /= static_cast<double>(subset.size());
  mb /= static_cast<double>(subset.size());
  std::vector<int> far(kBins, -1);
  std::vector<double> far_r(kBins, 0);
  for (int i : subset) {
    const double da = s.p[i].a - ma, db = s.p[i].b - mb, r = len2(da, db);
    const int b = std::clamp(static_cast<int>((std::atan2(db, da) + kPi) / (2 * kPi) * kBins), 0, kBins - 1);
    if (r > far_r[b]) {
      far_r[b] = r;
      far[b] = i;
    }
  }
  std::vector<std::array<double, 2>> outline;
  for (int b = 0; b < kBins; ++b)
    if (far[b] >= 0) outline.push_back({s.p[far[b]].a, s.p[far[b]].b});
  if (outline.size() < 0.75 * kBins) return {};
  return kasa_circle(outline);
}

bool cone_start_from_footprint(const Samples& s, const std::vector<int>& subset,
                               const std::vector<int>& side, double h0, double span,
                               std::array<double, 4>& start) {
  if (side.size() < 20) return false;
  const Circle rim = footprint_circle(s, subset);
  if (!rim.ok) return false;
  double sh = 0, shh = 0, sr = 0, srh = 0;
  for (int i : side) {
    const double t = (s.p[i].h - h0) / span, rho = len2(s.p[i].a - rim.x, s.p[i].b - rim.y);
    sh += t;
    shh += t * t;
    sr += rho;
    srh += rho * t;
  }
  const double n = static_cast<double>(side.size()), den = n * shh - sh * sh;
  const double k = std::abs(den) > 1e-12 ? (n * srh - sh * sr) / den : 0.0;
  const double r0 = (sr - k * sh) / n;
  start = {rim.x, rim.y, r0, r0 + k};
  return true;
}

// The points' widest extent across the plane (their 0.5 % to 99.5 % quantiles along
// each 15-degree azimuth, the largest): the chord of the widest section seen. A box's
// faces sit at their points' median, so a cone's box is as wide as its middle, not its
// foot (rooms 9855: a cone 12 cm wide at its foot, seen past a neighbour 8 cm wide, has
// a box 6 cm wide).
double points_span(const Samples& s) {
  constexpr int kAzimuths = 12;
  std::vector<double> x(s.p.size());
  double widest = 0;
  for (int k = 0; k < kAzimuths; ++k) {
    const double t = kPi * k / kAzimuths, cs = std::cos(t), sn = std::sin(t);
    for (size_t i = 0; i < s.p.size(); ++i) x[i] = cs * s.p[i].a + sn * s.p[i].b;
    widest = std::max(widest, quantile(x, 0.995) - quantile(x, 0.005));
  }
  return widest;
}

// Upright cone (or frustum): radius linear in height around a common axis, started
// from the cylinder fit. Valid only when it narrows (or widens) clearly.
Candidate fit_cone(const Samples& s, const std::vector<int>& subset, const Candidate& cyl,
                   const ShapeRecognizerParams& params) {
  Candidate c = cyl;
  c.model = Model::cone;
  c.valid = false;
  if (!cyl.valid) {
    // A cone flatter than the side test (flat_cone_sides) gives the cylinder fit no side:
    // its axis then comes from the footprint's outline.
    const Circle rim = params.flat_cone_sides ? footprint_circle(s, subset) : Circle{};
    if (!rim.ok || rim.r < params.min_radius_m || rim.r > params.max_radius_m) return c;
    Candidate start = cyl;
    start.ca = rim.x;
    start.cb = rim.y;
    start.r0 = start.r1 = rim.r;
    start.valid = true;
    return fit_cone(s, subset, start, params);
  }
  // A cone's side runs to the top of the points it is fitted to.
  {
    std::vector<double> hs;
    for (int i : subset) hs.push_back(s.p[i].h);
    c.h1 = std::max(cyl.h1, quantile(hs, 0.99));
  }
  const Candidate span_ref = c;
  std::vector<int> idx;
  std::vector<double> tol;
  // The side: the points within the span that `side` takes.
  const auto take_side = [&](auto side) {
    idx.clear();
    tol.clear();
    for (int i : subset)
      if (s.p[i].h > span_ref.h0 && s.p[i].h < span_ref.h1 && side(i)) {
        idx.push_back(i);
        tol.push_back(s.tol[i]);
      }
  };
  take_side([&](int i) { return !s.has_normals || std::abs(s.up[i]) < 0.9; });
  // A cone flatter than 26 degrees (a wide lid, a flat lampshade) faces up as much as
  // a top does: its side is then what lies below the top's height (flat_cone_sides).
  if (idx.size() < 20 && s.has_normals && params.flat_cone_sides)
    take_side([&](int i) { return s.p[i].h < span_ref.h1 - 2 * s.tol[i]; });
  if (idx.size() < 20) return c;
  const double span = std::max(span_ref.h1 - span_ref.h0, 1e-3);
  // Start from a straight line through the radius profile (robust to a bad cylinder).
  double sh = 0, shh = 0, sr = 0, srh = 0;
  for (int i : idx) {
    const double t = (s.p[i].h - span_ref.h0) / span;
    const double rho = len2(s.p[i].a - cyl.ca, s.p[i].b - cyl.cb);
    sh += t;
    shh += t * t;
    sr += rho;
    srh += rho * t;
  }
  const double n = static_cast<double>(idx.size());
  const double den = n * shh - sh * sh;
  double k = std::abs(den) > 1e-12 ? (n * srh - sh * sr) / den : 0.0;
  double r0 = (sr - k * sh) / n;
  std::array<double, 4> x{cyl.ca, cyl.cb, r0, r0 + k};
  // The terms of the parameters' point-free part, computed when the parameters change
  // (once per pass over the points), not per point: the same expressions, the same values.
  std::array<double, 4> terms_at;
  terms_at.fill(std::numeric_limits<double>::quiet_NaN());
  shape_residuals::ConeTerms terms;
  const auto residual = [&](const std::array<double, 4>& p, int j, shape_residuals::Gradient<4>* g) {
    if (std::memcmp(p.data(), terms_at.data(), sizeof p) != 0) {  // bit for bit
      terms = shape_residuals::cone_terms(p, span);
      terms_at = p;
    }
    const Local& q = s.p[idx[j]];
    return shape_residuals::cone(p, q.a, q.b, (q.h - span_ref.h0) / span, span, terms, g);
  };
  refine_sampled<4>(x, static_cast<int>(idx.size()), tol, residual, params.refine_sample_points);
  double taper_se = -1;  // counted once, when first asked
  const auto error = [&] {
    if (taper_se < 0) taper_se = taper_error(s, idx, span_ref.h0, span, params.focal_px);
    return taper_se;
  };
  c = cone_from_parameters(span_ref, x, params, error);
  // A tip run on to the apex leaves out the small flat top the camera saw under it, and
  // hides it (hidden_by_own_side; rooms 8022: a frustum 12 cm tall read as a cone 19 cm
  // tall): the frustum as fitted, when it explains clearly more.
  if (c.valid && c.r1 == 0 && x[3] > 0) {
    Candidate frustum = cone_from_parameters(span_ref, x, params, error, false);
    if (frustum.valid) {
      evaluate(c, s);
      evaluate(frustum, s);
      if (frustum.score > c.score + params.complexity_margin) c = frustum;
    }
  }
  // Started from a poor cylinder (a flat bowl seen from the side, a flat cone's side
  // read as a wider cylinder), the fit can run off to a cone wider than any of its points
  // or than any prop (a radius of metres whose arc follows the side): a second start
  // from the footprint's circle.
  if (std::max(c.r0, c.r1) > params.max_radius_m || cone_wider_than_its_points(s, subset, c)) {
    std::array<double, 4> y{};
    if (cone_start_from_footprint(s, subset, idx, span_ref.h0, span, y)) {
      refine_sampled<4>(y, static_cast<int>(idx.size()), tol, residual, params.refine_sample_points);
      Candidate second = cone_from_parameters(span_ref, y, params, error);
      if (second.valid && !cone_wider_than_its_points(s, subset, second)) {
        if (c.valid) {
          evaluate(c, s);
          evaluate(second, s);
        }
        if (!c.valid || second.score > c.score) c = second;
      }
    }
  }
  // A frustum widening up to a lid ends at the lid, as the cylinder does, not at its
  // points' 99 % height, which the noise lifts above it (held-out 5045: a flat bowl 2.4 m
  // away read as a cylinder). A cone narrowing up runs on to its tip above a small top.
  if (c.valid && c.r1 > c.r0 && cyl.lid_h > c.h0 + 0.005 && cyl.lid_h < c.h1) {
    c.r1 += (c.r1 - c.r0) * ((cyl.lid_h - c.h0) / (c.h1 - c.h0) - 1);
    c.h1 = cyl.lid_h;
  }
  return c;
}

// The curvature a sphere's points show across the view and along it (up the image):
// the depth along the ray to its centre fitted as a quadric of the two offsets across
// the ray, z = k0 + k1 x + k2 y + k3 x^2 + k4 y^2 + k5 x y. A sphere's near side has
// k3 = k4 = 1 / (2 r); an upright cylinder's or a cone's side has none along its axis, a
// box's face none at all. Returns {k3, k4}; zeros when the quadric is not determined.
std::array<double, 2> view_curvature(const Samples& s, const Candidate& c) {
  const Eigen::Vector3d centre(c.ca, c.cb, c.hc), eye(s.eye.a, s.eye.b, s.eye.h);
  const Eigen::Vector3d v = (centre - eye).normalized();
  const Eigen::Vector3d x = v.cross(Eigen::Vector3d(0, 0, 1)).normalized(), y = x.cross(v);
  Eigen::Matrix<double, 6, 6> ata = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> atb = Eigen::Matrix<double, 6, 1>::Zero();
  for (const Local& p : s.p) {
    const Eigen::Vector3d q = Eigen::Vector3d(p.a, p.b, p.h) - centre;
    const double px = q.dot(x), py = q.dot(y);
    Eigen::Matrix<double, 6, 1> row;
    row << 1, px, py, px * px, py * py, px * py;
    ata += row * row.transpose();
    atb += row * q.dot(v);
  }
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> solve(ata);
  if (solve.info() != Eigen::Success) return {0, 0};
  const Eigen::Matrix<double, 6, 1> k = solve.solve(atb);
  if (!k.allFinite()) return {0, 0};
  return {k[3], k[4]};
}

// The mean of points in plane coordinates (a cap's centre of mass).
Local mean_local(const std::vector<Local>& p) {
  Local m{0, 0, 0};
  for (const Local& q : p) {
    m.a += q.a;
    m.b += q.b;
    m.h += q.h;
  }
  const double n = static_cast<double>(std::max<size_t>(p.size(), 1));
  m.a /= n;
  m.b /= n;
  m.h /= n;
  return m;
}

// How far a sphere's fitted height or diameter may be from what rests on the plane: the
// fit's error on a seen cap grows with the radius, and is at least the sensor's 1.2 cm.
double sphere_slack(double r) { return std::max(0.012, 0.2 * r); }

Candidate fit_sphere(const Samples& s, const ShapeRecognizerParams& params) {
  Candidate c;
  c.model = Model::sphere;
  const int n = static_cast<int>(s.p.size());
  if (n < 12) return c;
  // Algebraic start: |p|^2 = 2 c.p + k.
  Eigen::Matrix4d a = Eigen::Matrix4d::Zero();
  Eigen::Vector4d b = Eigen::Vector4d::Zero();
  for (const Local& p : s.p) {
    const Eigen::Vector4d row(p.a, p.b, p.h, 1.0);
    a += row * row.transpose();
    b += row * (p.a * p.a + p.b * p.b + p.h * p.h);
  }
  const Eigen::Vector4d x0 = a.ldlt().solve(b);
  const double ca = x0[0] / 2, cb = x0[1] / 2, hc = x0[2] / 2;
  const double r2 = x0[3] + ca * ca + cb * cb + hc * hc;
  if (!std::isfinite(r2) || r2 <= 0) return c;
  std::array<double, 4> x{ca, cb, hc, std::sqrt(r2)};
  refine_analytic<4>(x, n, s.tol,
                     [&](const std::array<double, 4>& p, int i, shape_residuals::Gradient<4>* g) {
                       return shape_residuals::sphere(p, s.p[i].a, s.p[i].b, s.p[i].h, g);
                     });
  c.ca = x[0];
  c.cb = x[1];
  c.hc = x[2];
  c.r0 = std::abs(x[3]);
  // A resting sphere's centre is one radius above the plane.
  const bool resting = c.r0 >= params.min_radius_m && c.r0 <= params.max_radius_m &&
                       std::abs(c.hc - c.r0) < sphere_slack(c.r0);
  // Then it is fitted as resting: three parameters, its centre one radius up. A cap seen
  // alone (a dark ball lit only where it faces the camera) leaves the free fit's radius
  // and height ill-determined, while its top, seen from above, is the ball's: the
  // resting fit then starts from a radius of half the top, its centre that far beyond
  // the cap from the camera, and stands when its diameter keeps to the top.
  std::array<double, 3> y{c.ca, c.cb, (c.hc + c.r0) / 2};
  if (!resting) {
    if (!std::isfinite(c.hc) || s.top <= 0) return c;
    const Local m = mean_local(s.p);
    const double away = len2(m.a - s.eye.a, m.b - s.eye.b);
    const double r = s.top / 2;
    y = {m.a + (m.a - s.eye.a) / std::max(away, 1e-6) * r * params.sphere_cap_depth_share,
         m.b + (m.b - s.eye.b) / std::max(away, 1e-6) * r * params.sphere_cap_depth_share, r};
  }
  refine_analytic<3>(y, n, s.tol,
                     [&](const std::array<double, 3>& p, int i, shape_residuals::Gradient<3>* g) {
                       return shape_residuals::resting_sphere(p, s.p[i].a, s.p[i].b, s.p[i].h, g);
                     });
  c.ca = y[0];
  c.cb = y[1];
  c.hc = c.r0 = std::abs(y[2]);
  c.valid = c.r0 >= params.min_radius_m && c.r0 <= params.max_radius_m &&
            (resting || std::abs(2 * c.r0 - s.top) < sphere_slack(c.r0));
  // A sphere shows its curvature both across the view and along it: a strip of a
  // cylinder's or a cone's side curves across only, a box's edge along only
  // (view_curvature).
  if (c.valid) {
    const auto [across, along] = view_curvature(s, c);
    const double least = params.sphere_min_curvature_share / (2 * c.r0);
    c.valid = across >= least && along >= least;
  }
  return c;
}

// Points higher than this times Samples::bulk_top are not a flat torus's own
// (ShapeRecognizerParams::torus_own_points; the tube's noisy top lies under it).
constexpr double kTorusOwnHeight = 1.5;

// Torus lying flat on the plane: tube centre one minor radius above it.
Candidate fit_torus(const Samples& s, const Candidate& cyl, const ShapeRecognizerParams& params) {
  Candidate c;
  c.model = Model::torus;
  const int n = static_cast<int>(s.p.size());
  if (n < 20 || !cyl.valid) return c;
  std::vector<double> rho;
  for (const Local& p : s.p) rho.push_back(len2(p.a - cyl.ca, p.b - cyl.cb));
  const double minor0 = std::max(0.005, s.bulk_top / 2);
  std::array<double, 4> x{cyl.ca, cyl.cb, std::max(quantile(rho, 0.5), minor0 * 1.5), minor0};
  // A torus lying flat is no taller than its tube: points well above the bulk's top are
  // a neighbour's (a ball's edge beside a ring) and would pull the tube up round them.
  std::vector<int> own;
  std::vector<double> own_tol;
  for (int i = 0; i < n; ++i)
    if (!params.torus_own_points || s.p[static_cast<size_t>(i)].h <= kTorusOwnHeight * s.bulk_top) {
      own.push_back(i);
      own_tol.push_back(s.tol[static_cast<size_t>(i)]);
    }
  refine_analytic<4>(x, static_cast<int>(own.size()), own_tol,
                     [&](const std::array<double, 4>& p, int k, shape_residuals::Gradient<4>* g) {
                       const Local& q = s.p[static_cast<size_t>(own[static_cast<size_t>(k)])];
                       return shape_residuals::torus(p, q.a, q.b, q.h, g);
                     });
  c.ca = x[0];
  c.cb = x[1];
  c.major = std::abs(x[2]);
  c.minor = std::abs(x[3]);
  c.hc = c.minor;
  c.valid = c.minor >= 0.004 && c.major > 1.2 * c.minor && c.major + c.minor <= params.max_radius_m &&
            c.major >= params.min_radius_m;
  return c;
}

// Convex hull of 2D points (monotone chain), counter-clockwise.
std::vector<std::array<double, 2>> hull_2d(std::vector<std::array<double, 2>> pts) {
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return pts;
  std::vector<std::array<double, 2>> h(2 * pts.size());
  auto turn = [](const std::array<double, 2>& o, const std::array<double, 2>& a,
                 const std::array<double, 2>& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
  };
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && turn(h[k - 2], h[k - 1], pts[i]) <= 0) --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && turn(h[k - 2], h[k - 1], pts[i - 1]) <= 0) --k;
    h[k++] = pts[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// A box's azimuth from its side faces' points, fused with the side normals' estimate by
// their noise. Each side point belongs to the face its normal faces (faces parted at the
// footprint's middle), a face is a line in the footprint at its points' median offset,
// and Gauss-Newton turns the lines to fit the points (points off by more than their
// tolerance, an edge or a neighbour, do not steer). The lines fix the direction over the
// faces' whole length (two pieces of one box seen past a nearer object lie on one line);
// the normals' mean is biased on a small piece and noisy far away, but the lines are
// noisy too. Each estimate's variance: the normals' spread of 4x azimuth over 16 n, the
// lines' residual variance over the sum of squared positions along them (a slope's);
// the result is their inverse-variance mean (both sets of points share the smoothing, so
// its correlation scales both variances alike).
double refine_box_theta(const Samples& s, const std::vector<int>& sides, double theta_normals) {
  // The normals' estimate and its variance.
  double var_normals = 0;
  for (int i : sides) {
    const double d = std::remainder(4 * (std::atan2(s.nb[i], s.na[i]) - theta_normals), 2 * kPi);
    var_normals += d * d;
  }
  var_normals /= 16.0 * static_cast<double>(sides.size()) * static_cast<double>(sides.size());
  double theta = theta_normals, var_lines = -1;
  for (int iter = 0; iter < 6; ++iter) {
    const double cs = std::cos(theta), sn = std::sin(theta);
    std::vector<double> ax, ay;
    for (const Local& p : s.p) {
      ax.push_back(cs * p.a + sn * p.b);
      ay.push_back(-sn * p.a + cs * p.b);
    }
    const double xm = (quantile(ax, 0.005) + quantile(ax, 0.995)) / 2;
    const double ym = (quantile(ay, 0.005) + quantile(ay, 0.995)) / 2;
    // Per face (-x, +x, -y, +y): the offset, the position along it, the tolerance.
    std::vector<std::array<double, 3>> face[4];
    for (int i : sides) {
      const double x = ax[i], y = ay[i];
      const double nx = cs * s.na[i] + sn * s.nb[i], ny = -sn * s.na[i] + cs * s.nb[i];
      const double nh = len2(nx, ny);
      if (nh < 1e-6) continue;
      if (nx < -0.9 * nh && x < xm) face[0].push_back({x, y, s.tol[i]});
      if (nx > 0.9 * nh && x > xm) face[1].push_back({x, y, s.tol[i]});
      if (ny < -0.9 * nh && y < ym) face[2].push_back({y, -x, s.tol[i]});
      if (ny > 0.9 * nh && y > ym) face[3].push_back({y, -x, s.tol[i]});
    }
    double jj = 0, jr = 0, rr = 0;
    int m = 0;
    for (auto& f : face) {
      if (f.size() < 20) continue;
      std::vector<double> off;
      for (const auto& q : f) off.push_back(q[0]);
      const double d = quantile(off, 0.5);
      double sg = 0, sr = 0, w = 0;
      std::vector<std::array<double, 2>> in;
      for (const auto& q : f)
        if (std::abs(q[0] - d) < q[2]) {
          in.push_back({q[1], q[0] - d});
          sg += q[1];
          sr += q[0] - d;
          w += 1;
        }
      if (w < 20) continue;
      for (const auto& q : in) {
        const double g = q[0] - sg / w, r = q[1] - sr / w;
        jj += g * g;
        jr += g * r;
        rr += r * r;
        ++m;
      }
    }
    // Too short a face (under about 2 cm of spread) does not fix a direction.
    if (jj < 20 * 0.01 * 0.01 || m < 3) return theta_normals;
    const double step = std::clamp(-jr / jj, -0.05, 0.05);
    theta += step;
    // The lines' residual after the step, over the positions' spread: a slope's variance.
    var_lines = std::max(rr - jr * jr / jj, 0.0) / (m - 2) / jj;
    if (std::abs(step) < 1e-5) break;
  }
  if (var_lines < 0) return theta_normals;
  const double gain = var_normals / std::max(var_normals + var_lines, 1e-18);
  return theta_normals + gain * std::remainder(theta - theta_normals, kPi / 2);
}

// The azimuth of an upright box by its side normals, or by the footprint's minimum-area
// rectangle without them; fit_box's extents follow from it. Shared by the box of the
// normals and the box of the faces' lines (refine_box_theta), which differ only there.
struct BoxAzimuth {
  bool ok = false;
  double theta = 0;
  std::vector<int> sides;       // the side points (normals across the plane), empty without
  double theta_variance = 0;    // of the normals' estimate (rad^2), 0 without sides
  double half_diagonal = 0;     // of the footprint's minimum-area rectangle
};

BoxAzimuth box_azimuth(const Samples& s) {
  BoxAzimuth out;
  if (s.p.size() < 12) return out;
  std::vector<std::array<double, 2>> q;
  for (const Local& p : s.p) q.push_back({p.a, p.b});
  const auto hull = hull_2d(q);
  if (hull.size() < 3) return out;
  double best_area = 1e18, best_theta = 0;
  for (size_t i = 0; i < hull.size(); ++i) {
    const auto& p1 = hull[i];
    const auto& p2 = hull[(i + 1) % hull.size()];
    // The edge's unit direction (cos and sin of its azimuth); the angle is taken only
    // for the best edge.
    const double ex = p2[0] - p1[0], ey = p2[1] - p1[1], length = len2(ex, ey);
    const double cs = ex / length, sn = ey / length;
    double x0 = 1e18, x1 = -1e18, y0 = 1e18, y1 = -1e18;
    for (const auto& p : hull) {
      const double x = cs * p[0] + sn * p[1], y = -sn * p[0] + cs * p[1];
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
      y0 = std::min(y0, y);
      y1 = std::max(y1, y);
    }
    if ((x1 - x0) * (y1 - y0) < best_area) {
      best_area = (x1 - x0) * (y1 - y0);
      best_theta = std::atan2(ey, ex);
      out.half_diagonal = len2(x1 - x0, y1 - y0) / 2;
    }
  }
  // With normals, the side faces give the orientation (normal azimuths modulo 90
  // degrees, averaged as 4x angles) and, where the top overhangs (open flaps) or
  // stray points widen the footprint, the extents (two visible faces span it).
  std::vector<int> sides;
  if (s.has_normals) {
    double c4 = 0, s4 = 0;
    for (size_t i = 0; i < s.p.size(); ++i) {
      if (std::abs(s.up[i]) > 0.4) continue;
      const auto [cos4, sin4] = shape_residuals::fourfold(s.na[i], s.nb[i]);
      c4 += cos4;
      s4 += sin4;
      sides.push_back(static_cast<int>(i));
    }
    const double n = static_cast<double>(sides.size()), resultant = len2(c4, s4) / std::max(n, 1.0);
    if (sides.size() >= 30 && resultant > 0.3) {
      best_theta = std::atan2(s4, c4) / 4;
      // The mean direction's variance from the resultant length R of the 4x angles
      // (wrapped normal: a sample's variance -2 ln R), over n, over 16 for the 1x angle.
      out.theta_variance = -2 * std::log(resultant) / n / 16;
    } else {
      sides.clear();
    }
  }
  out.ok = true;
  out.theta = best_theta;
  out.sides = std::move(sides);
  return out;
}

// Upright box at azimuth `best_theta`: robust extents along its sides (the top face
// spans the footprint when seen from above); `sides` are the side points or empty.
Candidate box_at(const Samples& s, const ShapeRecognizerParams& params, double best_theta,
                 const std::vector<int>& sides) {
  Candidate c;
  c.model = Model::box;
  const double cs = std::cos(best_theta), sn = std::sin(best_theta);
  std::vector<double> xs, ys, sx, sy;
  for (const Local& p : s.p) {
    xs.push_back(cs * p.a + sn * p.b);
    ys.push_back(-sn * p.a + cs * p.b);
  }
  for (int i : sides) {
    sx.push_back(xs[i]);
    sy.push_back(ys[i]);
  }
  double x0 = quantile(xs, 0.005), x1 = quantile(xs, 0.995);
  double y0 = quantile(ys, 0.005), y1 = quantile(ys, 0.995);
  // The flat top: points facing up near the object's top (none without normals).
  std::vector<int> top_face;
  if (s.has_normals)
    for (size_t i = 0; i < s.p.size(); ++i)
      if (s.up[i] > 0.9 && s.p[i].h > s.top - std::max(0.02, 0.15 * s.top))
        top_face.push_back(static_cast<int>(i));
  if (!sides.empty()) {
    double sx0 = quantile(sx, 0.01), sx1 = quantile(sx, 0.99);
    double sy0 = quantile(sy, 0.01), sy1 = quantile(sy, 0.99);
    // A flat top seen at the box's height is the box itself, not an overhang: when
    // the visible side faces are shorter than it (one of them seen edge-on), the top
    // sets the extent.
    std::vector<double> tx, ty;
    for (int i : top_face) {
      tx.push_back(xs[i]);
      ty.push_back(ys[i]);
    }
    if (tx.size() >= 30) {
      sx0 = std::min(sx0, quantile(tx, 0.02));
      sx1 = std::max(sx1, quantile(tx, 0.98));
      sy0 = std::min(sy0, quantile(ty, 0.02));
      sy1 = std::max(sy1, quantile(ty, 0.98));
    }
    // Trust the faces where something sticks out beyond them (flaps, a neighbour's
    // stray points), provided they span most of the footprint.
    if (sx1 - sx0 > 0.5 * (x1 - x0) && (x1 - x0) - (sx1 - sx0) > 0.015) {
      x0 = sx0;
      x1 = sx1;
    }
    if (sy1 - sy0 > 0.5 * (y1 - y0) && (y1 - y0) - (sy1 - sy0) > 0.015) {
      y0 = sy0;
      y1 = sy1;
    }
  }
  // A seen face sits where its points are (their median), not at the extreme
  // quantile: bulged cartons and depth noise spread a face over several millimetres.
  if (!sides.empty()) {
    std::vector<double> face[4];  // -x, +x, -y, +y
    for (int i : sides) {
      const double nx = cs * s.na[i] + sn * s.nb[i], ny = -sn * s.na[i] + cs * s.nb[i];
      const double nh = len2(nx, ny);
      if (nh < 1e-6) continue;
      // Anywhere in its half of the footprint: stray points (a neighbour's edge) may
      // sit beyond the face and set the extreme quantile.
      if (nx < -0.9 * nh && xs[i] < (x0 + x1) / 2) face[0].push_back(xs[i]);
      if (nx > 0.9 * nh && xs[i] > (x0 + x1) / 2) face[1].push_back(xs[i]);
      if (ny < -0.9 * nh && ys[i] < (y0 + y1) / 2) face[2].push_back(ys[i]);
      if (ny > 0.9 * nh && ys[i] > (y0 + y1) / 2) face[3].push_back(ys[i]);
    }
    double* bound[4] = {&x0, &x1, &y0, &y1};
    for (int k = 0; k < 4; ++k)
      if (face[k].size() >= 20) *bound[k] = quantile(face[k], 0.5);
    // One face seen alone, and no top, measures the box's width and height but not its
    // depth: the extent across that face is the spread of its noise, not the box.
    const bool x_seen = face[0].size() >= 20 || face[1].size() >= 20;
    const bool y_seen = face[2].size() >= 20 || face[3].size() >= 20;
    const bool top_seen = top_face.size() >= 30 && top_face.size() >= s.p.size() / 10;
    c.depth_unseen = x_seen != y_seen && !top_seen;
  }
  const double xm = (x0 + x1) / 2, ym = (y0 + y1) / 2;
  c.theta = best_theta;
  c.ca = cs * xm - sn * ym;
  c.cb = sn * xm + cs * ym;
  c.ex = (x1 - x0) / 2;
  c.ey = (y1 - y0) / 2;
  if (c.ey > c.ex) {  // x along the longer side
    std::swap(c.ex, c.ey);
    c.theta += kPi / 2;
  }
  c.h0 = 0;
  c.h1 = s.top;
  // A flat top seen from above sets the height (stray points above it do not).
  if (top_face.size() >= 30 && top_face.size() >= s.p.size() / 10) {
    std::vector<double> top_h;
    for (int i : top_face) top_h.push_back(s.p[i].h);
    c.h1 = quantile(top_h, 0.5);
  }
  c.valid = c.ey >= params.min_radius_m / 2 && c.ex <= params.max_radius_m * 2 && c.h1 > 0.005;
  return c;
}

// Upright box: orientation of the minimum-area rectangle around the footprint, then
// robust extents along its sides (the top face spans the footprint when seen from above).
Candidate fit_box(const Samples& s, const ShapeRecognizerParams& params, const BoxAzimuth& azimuth) {
  if (!azimuth.ok) {
    Candidate c;
    c.model = Model::box;
    return c;
  }
  return box_at(s, params, azimuth.theta, azimuth.sides);
}

// A cylinder lying on the plane along azimuth `theta` through (ca, cb): a solid resting
// on its support touches it and does not pass through it, so its axis is parallel to the
// plane at the height of its radius. Given that, the cross-section is a circle touching
// the plane (2 parameters: offset across the axis and radius), which a partial view (a
// bottle's upper half) fixes as well as a whole one; the length from the 1/99 %
// quantiles along the axis.
Candidate fit_lying_cylinder_along(const Samples& s, double theta, double ca, double cb,
                                   double radius_start, const ShapeRecognizerParams& params) {
  Candidate c;
  c.model = Model::lying_cylinder;
  if (s.p.size() < 20) return c;
  const double cs = std::cos(theta), sn = std::sin(theta);
  std::vector<double> along(s.p.size()), w(s.p.size());
  for (size_t i = 0; i < s.p.size(); ++i) {
    along[i] = cs * (s.p[i].a - ca) + sn * (s.p[i].b - cb);
    w[i] = -sn * (s.p[i].a - ca) + cs * (s.p[i].b - cb);
  }
  const double lo = quantile(along, 0.01), hi = quantile(along, 0.99);
  // The circle through the side's points: a cap's lie inside it and would shrink it (a
  // short tin on its side shows a lid as large as its side). Caps face along the axis.
  std::vector<int> side;
  std::vector<double> side_tol;
  for (size_t i = 0; i < s.p.size(); ++i)
    if (!s.has_normals || std::abs(cs * s.na[i] + sn * s.nb[i]) < kSideNormalAlong) {
      side.push_back(static_cast<int>(i));
      side_tol.push_back(s.tol[i]);
    }
  std::array<double, 2> x{0.0, std::max(0.005, radius_start)};
  refine_analytic<2>(x, static_cast<int>(side.size()), side_tol,
                     [&](const std::array<double, 2>& p, int k, shape_residuals::Gradient<2>* g) {
                       const auto i = static_cast<size_t>(side[static_cast<size_t>(k)]);
                       return shape_residuals::lying_circle(p, w[i], s.p[i].h, g);
                     });
  const double mid = (lo + hi) / 2;
  c.theta = theta;
  c.ca = ca + cs * mid - sn * x[0];
  c.cb = cb + sn * mid + cs * x[0];
  c.r0 = c.r1 = std::abs(x[1]);
  c.hc = c.r0;
  c.ex = (hi - lo) / 2;
  c.valid = c.r0 >= params.min_radius_m && c.r0 <= params.max_radius_m && c.ex > c.r0 * 0.5;
  return c;
}

// The oriented box's least half extent: thinner than that, the fit cannot tell.
constexpr double kThinnestBoxHalf_m = 0.0025;

// A box no thicker than its points' tolerance is one face's noise: one face seen (a
// furniture panel at a grazing angle, a carton face-on), its depth not measured. So is
// one at the fit's thinnest (a wall 2 m away seen by a time-of-flight camera spans 4 mm,
// under the 5 mm the fit reports, its tolerance 4.6 mm).
bool one_face_thick(const ShapeFit& box, const Samples& s) {
  if (s.tol.empty()) return false;
  const auto& d = box.primitive.dimensions_m;
  const double thin = std::max(quantile(s.tol, 0.5), 2 * kThinnestBoxHalf_m);
  return *std::min_element(d.begin(), d.end()) <= thin;
}

// A box in any orientation (a laptop lid leaning back, a book on its edge): axes
// from the points' principal directions, extents from robust quantiles. Tried only
// when no shape standing on the plane explains the object.
ShapeFit fit_oriented_box(const Samples& s, const ShapeRecognizerParams& params) {
  ShapeFit out;
  const size_t n = s.xyz.size();
  if (n < 30) return out;
  const PointScatter scatter = point_scatter(s.xyz);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scatter.scatter);
  Vec3 axes[3];
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = es.eigenvectors().col(2 - k);  // largest first
    axes[k] = normalized(Vec3{e.x(), e.y(), e.z()});
    std::vector<double> t;
    for (const Vec3& p : s.xyz) t.push_back(dot(p, axes[k]));
    lo[k] = quantile(t, 0.01);
    hi[k] = quantile(t, 0.99);
  }
  double half[3];
  Vec3 center;
  for (int k = 0; k < 3; ++k) {
    half[k] = std::max((hi[k] - lo[k]) / 2, kThinnestBoxHalf_m);
    center = center + axes[k] * ((hi[k] + lo[k]) / 2);
  }
  double covered = 0, sq = 0;
  for (size_t i = 0; i < n; ++i) {
    const Vec3 d = s.xyz[i] - center;
    double o[3], outside = 0, inside = 1e9;
    for (int k = 0; k < 3; ++k) {
      o[k] = std::abs(dot(d, axes[k])) - half[k];
      outside += std::pow(std::max(o[k], 0.0), 2);
      inside = std::min(inside, -o[k]);
    }
    const double dist = outside > 0 ? std::sqrt(outside) : inside;
    if (dist < s.tol[i]) {
      covered += 1;
      sq += dist * dist;
    }
  }
  if (2 * half[1] < params.min_radius_m || 2 * half[0] > 2 * params.max_radius_m) return out;
  out.primitive.kind = ShapeKind::box;
  out.primitive.dimensions_m = {2 * half[0], 2 * half[1], 2 * half[2]};
  out.primitive.center = center;
  out.primitive.axis = axes[2];
  out.x_axis = axes[0];
  out.coverage = covered / static_cast<double>(n);
  out.rms_m = covered > 0 ? std::sqrt(sq / covered) : 0;
  out.primitive.fit = out.coverage;
  return out;
}

ShapeFit to_fit(const Candidate& c, const PlaneFrame& f) {
  ShapeFit out;
  PhysicalPrimitive& p = out.primitive;
  const Vec3 up = f.n;
  out.x_axis = f.u;
  switch (c.model) {
    case Model::sphere:
      p.kind = ShapeKind::sphere;
      p.dimensions_m = {c.r0};
      p.center = f.to_world(c.ca, c.cb, c.hc);
      p.axis = up;
      break;
    case Model::cylinder:
      p.kind = ShapeKind::cylinder;
      p.dimensions_m = {c.r0, c.h1 - c.h0};
      p.center = f.to_world(c.ca, c.cb, (c.h0 + c.h1) / 2);
      p.axis = up;
      break;
    case Model::cone: {
      const double wide = std::max(c.r0, c.r1), narrow = std::min(c.r0, c.r1);
      if (c.as_cylinder) {
        p.kind = ShapeKind::cylinder;
        p.dimensions_m = {(wide + narrow) / 2, c.h1 - c.h0};
        p.center = f.to_world(c.ca, c.cb, (c.h0 + c.h1) / 2);
        p.axis = up;
        break;
      }
      // The axis points from the base (wide end) to the apex.
      p.kind = ShapeKind::cone;
      const bool narrowing = c.r1 <= c.r0;
      p.dimensions_m = {wide, c.h1 - c.h0};
      p.narrow_radius_m = narrow;  // 0 for a pointed cone
      p.center = f.to_world(c.ca, c.cb, (c.h0 + c.h1) / 2);
      p.axis = narrowing ? up : up * -1.0;
      break;
    }
    case Model::torus:
      p.kind = ShapeKind::torus;
      p.dimensions_m = {c.major, c.minor};
      p.center = f.to_world(c.ca, c.cb, c.hc);
      p.axis = up;
      break;
    case Model::box:
      p.kind = ShapeKind::box;
      p.dimensions_m = {2 * c.ex, 2 * c.ey, c.h1 - c.h0};
      p.center = f.to_world(c.ca, c.cb, (c.h0 + c.h1) / 2);
      p.axis = up;
      out.x_axis = f.dir(std::cos(c.theta), std::sin(c.theta), 0);
      break;
    case Model::lying_cylinder:
      p.kind = ShapeKind::cylinder;
      p.dimensions_m = {c.r0, 2 * c.ex};
      p.center = f.to_world(c.ca, c.cb, c.hc);
      p.axis = f.dir(std::cos(c.theta), std::sin(c.theta), 0);
      out.x_axis = up;
      break;
  }
  p.fit = c.coverage;
  out.rms_m = c.rms;
  out.coverage = c.coverage;
  return out;
}

// Parameters each resting shape fits given the support plane: the axis position (2),
// then a sphere's radius (its centre one radius up); a cylinder's radius and height; a
// cone's two radii and height; a torus's two radii; a box's azimuth, two sides and
// height; a lying cylinder's azimuth, offset, position along it, radius and length.
int parameter_count(Model m) {
  switch (m) {
    case Model::sphere: return 3;
    case Model::cylinder: return 4;
    case Model::cone: return 5;
    case Model::torus: return 4;
    case Model::box: return 6;
    case Model::lying_cylinder: return 6;
  }
  return 6;
}

}  // namespace

int fitted_parameter_count(const ShapeFit& fit, const Plane& support) {
  switch (fit.primitive.kind) {
    case ShapeKind::sphere: return parameter_count(Model::sphere);
    case ShapeKind::cylinder:
      // Upright: the axis is the support's normal (within a degree).
      return parameter_count(std::abs(dot(fit.primitive.axis, support.normal)) > 0.9998 ? Model::cylinder
                                                                                        : Model::lying_cylinder);
    case ShapeKind::cone: return parameter_count(Model::cone);
    case ShapeKind::torus: return parameter_count(Model::torus);
    case ShapeKind::box:
    case ShapeKind::plane: return parameter_count(Model::box);
  }
  return parameter_count(Model::box);
}

namespace {

struct SelectionEntry {
  double evidence = 0;  // MSAC score (1 - mean (d / tol)^2), side-shape penalty included
  double coverage = 0, rms_m = 0;
  int parameters = 0;
};

// The number of independent noise samples among the points: the scanner smooths each
// point over its neighbours within max(1.2 cm, 3 sigma_z, 6 pixels) at its depth (its
// default MLS radius and window, scanner.cpp smooth_cluster), so points that close share
// their noise. Each point counts one over the number of points in its neighbourhood,
// counted on every k-th point (k x that count) so that it costs at most 200 per point.
double independent_points(const Samples& s, double focal_px) {
  const size_t stride = std::max<size_t>(1, s.xyz.size() / 200);
  double n = 0;
  for (size_t i = 0; i < s.xyz.size(); ++i) {
    const double z = std::abs(s.xyz[i].z);
    const double r = shared_noise_radius_m(z, focal_px, s.noise);
    size_t near = 0;
    for (size_t j = i % stride; j < s.xyz.size(); j += stride) {
      const Vec3 d = s.xyz[j] - s.xyz[i];
      near += dot(d, d) < r * r;
    }
    n += 1.0 / static_cast<double>(std::max<size_t>(near * stride, 1));
  }
  return n;
}

// How bunched the normals are into faces 90 degrees apart, in a plane `direction(i)`
// gives point i's normal in (nullopt: not counted): |mean of 4x their angle|, near 1
// for faces, near 0 for a round side; -1 without normals or with fewer than 30 counted.
template <typename Direction>
double normals_flatness(const Samples& s, Direction direction) {
  if (!s.has_normals) return -1;
  double c4 = 0, s4 = 0;
  int n = 0;
  for (size_t i = 0; i < s.p.size(); ++i) {
    const std::optional<std::array<double, 2>> d = direction(i);
    if (!d) continue;
    const auto [cos4, sin4] = shape_residuals::fourfold((*d)[0], (*d)[1]);
    c4 += cos4;
    s4 += sin4;
    ++n;
  }
  return n >= 30 ? len2(c4, s4) / n : -1.0;
}

// How far each normal seen lies from a box's or a lying cylinder's: sin^2 of the angle
// between it and the model's at the nearest surface point; -1 where the normal is
// unknown. The normals' own noise adds the same to every model, so two models' misfits
// compare even where that noise is large.
std::vector<double> normal_misfits(const Candidate& c, const Samples& s) {
  std::vector<double> out(s.p.size(), -1);
  if (!s.has_normals) return out;
  const CandidateTerms k = terms_of(c);
  for (size_t i = 0; i < s.p.size(); ++i) {
    const double n2 = s.na[i] * s.na[i] + s.nb[i] * s.nb[i] + s.up[i] * s.up[i];
    if (n2 < 0.25) continue;  // unknown (0)
    const std::array<double, 3> m = model_normal(c, k, s.p[i]);
    const double cosine = m[0] * s.na[i] + m[1] * s.nb[i] + m[2] * s.up[i];
    out[i] = 1 - cosine * cosine / n2;
  }
  return out;
}

// The flatness of the side normals across a level axis along azimuth `theta`: of their
// angles in the upright plane across the axis, the caps' left out (kSideNormalAlong).
double flatness_across(const Samples& s, double theta) {
  const double cs = std::cos(theta), sn = std::sin(theta);
  return normals_flatness(s, [&](size_t i) -> std::optional<std::array<double, 2>> {
    if (std::abs(cs * s.na[i] + sn * s.nb[i]) > kSideNormalAlong) return std::nullopt;
    return std::array<double, 2>{-sn * s.na[i] + cs * s.nb[i], s.up[i]};
  });
}

// Whether the normals may sweep round a level axis along azimuth `theta` (flatness
// across it under kRoundAcrossAxis): asked before a lying cylinder is fitted along it,
// so that no fit is spent on a box's faces. Unknown normals show nothing.
bool round_across(const Samples& s, double theta) {
  const double across = flatness_across(s, theta);
  return across >= 0 && across < kRoundAcrossAxis;
}

// Whether a lying cylinder's normals show it, since its points alone do not: a box
// resting where it does explains them as well, within the noise, from about 2 m. Its
// normals (round_across its axis) must lie nearer its normals than the box's faces', by
// kRoundNormalsSigmas standard errors of the mean difference over the object's
// independent points: noisy normals sweep round a box's faces too (far away, or from a
// stereo camera).
// `boxes`: normal_misfits of the box (empty when it is not valid); `independent`:
// independent_points of the object.
bool nearer_than_box_faces(const Candidate& lying, const std::vector<double>& boxes,
                           const Samples& s, double independent) {
  constexpr double kRoundNormalsSigmas = 1;
  if (!lying.valid) return false;
  if (boxes.empty()) return true;
  const std::vector<double> own = normal_misfits(lying, s);
  double sum = 0, sum2 = 0;
  int n = 0;
  for (size_t i = 0; i < own.size(); ++i)
    if (own[i] >= 0) {
      const double d = boxes[i] - own[i];
      sum += d;
      sum2 += d * d;
      ++n;
    }
  if (n < 2) return false;
  const double mean = sum / n, spread = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
  return mean > kRoundNormalsSigmas * spread / std::sqrt(std::max(1.0, independent));
}

// The least criterion among the entries (the saturated ones alone when
// `saturated_only`), sigma the smallest RMS among the saturated; -1 when none is.
int least_criterion(const std::vector<SelectionEntry>& entries, double n, double mean_tol2,
                    double saturated, bool saturated_only) {
  double sigma = 1e9;
  for (const SelectionEntry& e : entries)
    if (e.coverage >= saturated && e.rms_m > 0) sigma = std::min(sigma, e.rms_m);
  if (sigma >= 1e9 || n <= 0) return -1;
  sigma = std::max(sigma, 1e-4);
  int pick = -1;
  double least = 1e300;
  for (size_t i = 0; i < entries.size(); ++i) {
    const SelectionEntry& e = entries[i];
    if (saturated_only && e.coverage < saturated) continue;
    const double bic = n * std::max(0.0, 1 - e.evidence) * mean_tol2 / (sigma * sigma) +
                       e.parameters * std::log(std::max(n, 2.0));
    if (bic < least) {
      least = bic;
      pick = static_cast<int>(i);
    }
  }
  return pick;
}

// The saturated candidate (coverage >= `saturated`) with the least BIC over n independent
// points, n (1 - evidence) tol^2 / sigma^2 + k ln n: (1 - evidence) tol^2 is their mean
// truncated squared residual, sigma the noise, estimated by the smallest RMS among the
// saturated candidates (an upper bound of it). -1 when none is saturated.
int saturated_choice(const std::vector<SelectionEntry>& entries, double n, double mean_tol2,
                     double saturated) {
  return least_criterion(entries, n, mean_tol2, saturated, true);
}

// The best candidate by rank leaves points unexplained, and a candidate that paid the
// complexity margin explains (nearly) all of them: a bowl's flared side that the cylinder
// of its rim cannot reach. The margin is a fixed share of the score whatever the number
// of points, while the unexplained points are evidence that grows with their number: the
// two are compared by the information criterion instead, n (1 - evidence) tol^2 / sigma^2
// + k ln n over n independent points (an unexplained point costs tol^2, the truncation of
// the score), sigma the smallest RMS among the saturated (an upper bound of the noise;
// the unsaturated best's RMS counts only the points it explains). entries[0] is the best
// by rank, the others the saturated candidates that paid the margin; returns the index
// into entries of the least criterion.
int margin_paid_choice(const std::vector<SelectionEntry>& entries, double n, double mean_tol2,
                       double saturated) {
  return std::max(0, least_criterion(entries, n, mean_tol2, saturated, false));
}

// A body that explains too little alone is weighed with its neck only when it explains
// this share of the points itself.
constexpr double kBodyLeastShare = 0.5;

// A neck's upper part: above this share of its height. Lower down it widens into the
// shoulder, whose points the neck's cylinder, fitted on its lower part as a body's is,
// takes in (rooms 12102: 2.3 cm, its upper part's circle 1.9 cm, on a body of 3.5 cm).
constexpr double kNeckUpperFrom = 0.4;

// The radius of the circle through the side points of a neck's upper part (`rest`, from
// `base` up), 0 when too few are seen; on a generator of its own, so that measuring it
// draws nothing from the fit's.
double neck_top_radius(const Samples& s, const std::vector<int>& rest, double base,
                       const ShapeRecognizerParams& params) {
  const Footprint f = side_footprint(s, rest, height_share(s, rest, base, kNeckUpperFrom),
                                     std::numeric_limits<double>::infinity());
  std::mt19937_64 own(params.seed);
  const Circle top = robust_circle(f.q, f.tol, params, own);
  return top.ok ? top.r : 0.0;
}

// Whether a body and its neck (a bottle's cylinder and the cone or cylinder above it)
// explain the points closer than one cone through both, by the information criterion
// (least_criterion) over n independent points: each point's residual to the nearer of
// the two, truncated at its tolerance, against the cone's; the pair pays for its
// parameters. Only when the pair too covers `saturated` of the points.
bool pair_over_cone(const Samples& s, const Candidate& body, const Candidate& neck,
                    const Candidate& cone, double n, double mean_tol2, double saturated) {
  const CandidateTerms tb = terms_of(body), tn = terms_of(neck), tc = terms_of(cone);
  double pair_score = 0, cone_score = 0, pair_sq = 0, cone_sq = 0;
  int pair_in = 0, cone_in = 0;
  for (size_t i = 0; i < s.p.size(); ++i) {
    const double dp = std::min(distance(body, tb, s.p[i]), distance(neck, tn, s.p[i]));
    const double dc = distance(cone, tc, s.p[i]);
    if (dp < s.tol[i])
      pair_score += 1 - (dp / s.tol[i]) * (dp / s.tol[i]), pair_sq += dp * dp, ++pair_in;
    if (dc < s.tol[i])
      cone_score += 1 - (dc / s.tol[i]) * (dc / s.tol[i]), cone_sq += dc * dc, ++cone_in;
  }
  const double count = static_cast<double>(std::max<size_t>(s.p.size(), 1));
  const auto rms = [](double sq, int in) { return in > 0 ? std::sqrt(sq / in) : 0.0; };
  const std::vector<SelectionEntry> entries{
      {cone_score / count, cone_in / count, rms(cone_sq, cone_in), parameter_count(cone.model)},
      {pair_score / count, pair_in / count, rms(pair_sq, pair_in),
       parameter_count(body.model) + parameter_count(neck.model)}};
  return entries[1].coverage >= saturated &&
         saturated_choice(entries, n, mean_tol2, saturated) == 1;
}

// Points credited half (a lid's, a rim's lip or handle: in_lid, in_rim_part) are no
// evidence against a shape, and no evidence for it either: they must not make it win
// over a rival that explains more of the points as its own surface, and closer. Far
// away the rim-part band (a third of the radius plus the tolerance, 4 cm at 3.3 m)
// takes in a box's corners round the cylinder inscribed in it (nyu_basement's bin:
// the cylinder r 0.15 m explains 86 % of the points within tolerance and 13 % as rim
// parts, the box 97 % at a lower RMS). Returns the rival with the best rank less its
// credit when one explains more, at a lower RMS, and ranks above the best once credits
// are set aside; else `best`.
int credited_rival(const std::vector<Candidate>& cands, const std::vector<double>& rank,
                   const std::vector<char>& judged, int best) {
  const Candidate& b = cands[static_cast<size_t>(best)];
  if (b.credit <= 0) return best;
  int pick = best;
  double plain = rank[static_cast<size_t>(best)] - b.credit;
  for (size_t i = 0; i < cands.size(); ++i) {
    const Candidate& c = cands[i];
    if (static_cast<int>(i) == best || !judged[i] || !c.valid) continue;
    if (c.explained > b.explained && c.rms < b.rms && rank[i] - c.credit > plain) {
      plain = rank[i] - c.credit;
      pick = static_cast<int>(i);
    }
  }
  return pick;
}

// A round top with nothing seen below its rim where an upright cylinder's side would
// face the camera: a body narrowing under its rim (a bowl, a pot or a lampshade widening
// up, seen from above), whose side faces down, hidden by the rim. The cylinder predicts
// its near side's pixels in a band below the rim (clear of the rim's noise and of the
// table): the side's projected area, about 2 r x band x cos(elevation), over a pixel's
// footprint (range / f)^2, times the share of the points sampled. A frustum widening up
// hides its side from the eye (D from the axis, E above the plane) when its foot is no
// wider than r - (D - r) h / (E - h); that widest foot is its narrow end. Nothing when
// the side would be a few pixels, when it shows, or when no frustum on a stable foot
// could hide it (then something nearer hides it, not the rim).
std::optional<Candidate> frustum_under_rim(const Samples& s, const Candidate& cyl, double sampled,
                                           const ShapeRecognizerParams& params) {
  if (cyl.model != Model::cylinder || !cyl.valid || s.tol.empty()) return std::nullopt;
  const double r = cyl.r1, h = cyl.h1 - cyl.h0;
  const double d = len2(s.eye.a - cyl.ca, s.eye.b - cyl.cb), e = s.eye.h - cyl.h0;
  if (h <= 0 || e <= h || d <= r) return std::nullopt;
  const double foot = r - (d - r) * h / (e - h);
  if (foot < params.min_foot_share * r) return std::nullopt;
  const double tol = quantile(s.tol, 0.5);
  const double lo = cyl.h0 + 0.15 * h, hi = cyl.h1 - std::max(2 * tol, 0.25 * h);
  if (hi <= lo) return std::nullopt;
  const double range = len2(d, e - 0.5 * (lo + hi));
  const double fx = params.focal_px;
  const double expected = sampled * 2 * r * (hi - lo) * (d / range) * (fx / range) * (fx / range);
  if (expected < 30) return std::nullopt;  // a few pixels: nothing to tell
  int seen = 0;
  for (const Local& p : s.p) seen += p.h > lo && p.h < hi;
  if (seen > params.max_side_seen_share * expected) return std::nullopt;
  Candidate c = cyl;
  c.model = Model::cone;
  c.r0 = foot;
  c.r1 = r;
  c.as_cylinder = false;
  c.floor_h = -1;
  return c;
}

// Whether the camera saw the support's point g through an upright cylinder's, cone's or
// box's solid shrunk by `model` but for its foot (the share its fit leaves unsure): g
// lies inside the shrunk foot, and the ray from the eye to g runs inside the shrunk solid
// for more than `noise` before g (ray_into_solid). The depth noise moves a point along
// its ray, so that is how far behind the solid's surface the noise could have put a
// point of it. Only g inside the foot counts: the table seen behind an object over its
// top tells how well a primitive follows a rounded top, not what stands there.
// With `along_ray` false, the solid is shrunk by `noise` too, in every direction, and any
// run inside it counts.
bool seen_through(const Candidate& c, const CandidateTerms& k, Local eye, Local g, double model,
                  double noise, bool along_ray) {
  // Its foot stays on the support (where g lies): only its top and sides move in.
  if (!along_ray) {
    const RayIntoSolid r = ray_into_solid(c, k, eye, g, model + noise, model + noise, 0);
    return r.inside_foot && r.hit.t < r.length;
  }
  const RayIntoSolid r = ray_into_solid(c, k, eye, g, model, model, 0);
  return r.inside_foot && r.length - r.hit.t > noise;
}

// The height under which an object's points are its foot: a face running down to its
// support reaches it.
constexpr double kFaceFootHeight = 0.03;

// Drops from the support's surface around the object the points right under its own
// lowest points (within kFaceFootHeight of the plane, a point's tolerance across): there
// the object's face runs on down into the band, its own foot, not the table seen.
void drop_ground_under_faces(Samples& s) {
  std::vector<Local> low;
  for (const Local& p : s.p)
    if (p.h < kFaceFootHeight) low.push_back(p);
  s.foot_points = static_cast<int>(low.size());
  if (low.empty()) return;
  // Sorted along a, each surface point asks only the low points within its tolerance
  // there (the surface's thousands against the foot's hundreds, per object and frame).
  std::sort(low.begin(), low.end(), [](const Local& x, const Local& y) { return x.a < y.a; });
  size_t kept = 0;
  for (size_t i = 0; i < s.ground.size(); ++i) {
    const Local& g = s.ground[i];
    const double t = s.ground_tol[i];
    const auto from = std::lower_bound(low.begin(), low.end(), g.a - t,
                                       [](const Local& p, double a) { return p.a < a; });
    bool under = false;
    for (auto p = from; p != low.end() && p->a < g.a + t && !under; ++p)
      under = len2(p->a - g.a, p->b - g.b) < t;
    if (under) continue;
    s.ground[kept] = g;
    s.ground_tol[kept++] = t;
  }
  s.ground.resize(kept);
  s.ground_tol.resize(kept);
}

// The distances from the axis of the support's points the camera saw through an upright
// cylinder, cone or box (min_foot_seen_pixels), its solid shrunk by
// foot_seen_model_share of its foot's size, by more than each point's tolerance along its
// ray (seen_through); none for the other shapes. A box
// only when the object reaches down to its support (kMinFootPoints of its points within
// kFaceFootHeight): a box standing on another and overhanging it shows the table under
// it (OSD learn18) and is still a box, while a body narrowing under its rim (a cup seen
// from above) has no box's alternative to give way to.
std::vector<double> seen_through_radii(const Samples& s, const Candidate& c,
                                       const ShapeRecognizerParams& params) {
  constexpr int kMinFootPoints = 10;
  const bool box = c.model == Model::box && s.foot_points >= kMinFootPoints;
  if (c.model != Model::cylinder && c.model != Model::cone && !box) return {};
  const CandidateTerms k = terms_of(c);
  const double model = params.foot_seen_model_share * (box ? std::min(c.ex, c.ey) : c.r0);
  std::vector<double> radii;
  for (size_t i = 0; i < s.ground.size(); ++i)
    if (seen_through(c, k, s.eye, s.ground[i], model, s.ground_tol[i], params.foot_seen_along_ray))
      radii.push_back(len2(s.ground[i].a - c.ca, s.ground[i].b - c.cb));
  return radii;
}

// The frustum an upright cylinder gives when the support's surface was seen through it
// at `radii` from its axis: its rim on the foot that surface leaves free, the radius
// inside which the surface is not seen (past the share of those points that the noise
// puts inside, kFootNoiseShare). A cup widening up seen from above shows the table in the
// ring between its foot and its rim. Nothing when that foot would not narrow the rim by
// min_cone_taper or is under min_radius_m (the table seen through a ring's hole).
std::optional<Candidate> frustum_on_free_foot(const Candidate& cyl,
                                              const std::vector<double>& radii,
                                              const ShapeRecognizerParams& params) {
  constexpr double kFootNoiseShare = 0.05;
  if (radii.empty()) return std::nullopt;
  const double foot = quantile(radii, kFootNoiseShare);
  if (foot > (1 - params.min_cone_taper) * cyl.r1 || foot < params.min_radius_m)
    return std::nullopt;
  Candidate c = cyl;
  c.model = Model::cone;
  c.r0 = foot;
  c.as_cylinder = false;
  c.floor_h = -1;
  return c;
}

// A cylinder in any orientation whose cross-section through its centre reaches below the
// plane by more than twice the points' median noise tolerance (the centre's height and
// the radius are each fitted to within about one) passes through the support it stands
// on: the cylinder lying on the plane along the same azimuth
// (fit_lying_cylinder_along), scored as the resting shapes are. The centre's cross-
// section, not the ends: the centre and the radius are what the visible arc fixes, the
// axis's tilt is not (a bottle cut by the image border, its fitted axis dipping 2 to 4 cm
// into the floor at one end while its centre sits one radius up). Nothing when it does
// not pass through (it rests on the plane or on something else) or when its axis is
// near upright (no azimuth).
std::optional<Candidate> resting_lying_cylinder(const Samples& s, const ShapeFit& fit,
                                                const PlaneFrame& frame,
                                                const ShapeRecognizerParams& params) {
  const PhysicalPrimitive& prim = fit.primitive;
  if (prim.dimensions_m.size() < 2 || s.tol.empty()) return std::nullopt;
  const Vec3 axis = normalized(prim.axis);
  const double up = std::abs(dot(axis, frame.n));
  const Local centre = frame.to_local(prim.center);
  const double r = prim.dimensions_m[0];
  const double lowest = centre.h - r * std::sqrt(std::max(0.0, 1 - up * up));
  if (lowest >= -2 * quantile(s.tol, 0.5)) return std::nullopt;
  const double da = dot(axis, frame.u), db = dot(axis, frame.v);
  if (len2(da, db) < 1e-6) return std::nullopt;
  Candidate c = fit_lying_cylinder_along(s, std::atan2(db, da), centre.a, centre.b,
                                         std::min(r, std::max(0.005, s.top / 2)), params);
  if (!c.valid) return std::nullopt;
  evaluate(c, s);
  return c;
}

// Subsample deterministically: a seeded shuffle keeps the spatial spread.
std::vector<int> pick_indices(size_t n, int max_points, std::mt19937_64& rng) {
  std::vector<int> idx(n);
  std::iota(idx.begin(), idx.end(), 0);
  if (static_cast<int>(n) > max_points) {
    std::shuffle(idx.begin(), idx.end(), rng);
    idx.resize(max_points);
    std::sort(idx.begin(), idx.end());
  }
  return idx;
}

}  // namespace

ObjectShape recognize_object_shape(const std::vector<Vec3>& points,
                                   const std::vector<Vec3>& normals, const Plane& support,
                                   const ShapeRecognizerParams& params,
                                   const SupportAround& around) {
  ObjectShape out;
  if (points.size() < 12) return out;
  std::mt19937_64 rng(params.seed);
  const PlaneFrame frame = make_frame(support);
  Samples s;
  s.has_normals = normals.size() == points.size();
  for (int i : pick_indices(points.size(), params.max_fit_points, rng)) {
    const Vec3& p = points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    s.p.push_back(frame.to_local(p));
    s.xyz.push_back(p);
    s.up.push_back(s.has_normals ? dot(normals[i], frame.n) : 0.0);
    s.na.push_back(s.has_normals ? dot(normals[i], frame.u) : 0.0);
    s.nb.push_back(s.has_normals ? dot(normals[i], frame.v) : 0.0);
    s.tol.push_back(std::max(params.min_tolerance_m,
                             params.noise_factor * params.depth_noise.sigma_z(std::abs(p.z))));
  }
  if (s.p.size() < 12) return out;
  s.eye = frame.to_local(Vec3{0, 0, 0});
  s.own_side_hides = params.own_side_hides;
  s.noise = params.depth_noise;
  // The support around, an even sample of at most kMostGround points (every k-th).
  constexpr size_t kMostGround = 4000;
  const size_t ground_step = around.points.size() / kMostGround + 1;
  s.ground_pixels = static_cast<double>(std::max(1, around.pixels_per_point) * ground_step);
  for (size_t i = 0; i < around.points.size(); i += ground_step) {
    const Vec3& p = around.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    s.ground.push_back(frame.to_local(p));
    s.ground_tol.push_back(std::max(
        params.min_tolerance_m, params.noise_factor * params.depth_noise.sigma_z(std::abs(p.z))));
  }
  std::vector<double> hs;
  for (const Local& p : s.p) hs.push_back(p.h);
  s.top = quantile(hs, 0.99);
  s.bulk_top = params.torus_own_points ? quantile(hs, 0.9) : s.top;
  drop_ground_under_faces(s);

  std::vector<int> all(s.p.size());
  std::iota(all.begin(), all.end(), 0);
  std::vector<Candidate> cands;
  // The box fit's footprint gates the shapes whose proportions cannot match it
  // (a torus is flat, a sphere as tall as it is wide): cheaper and fewer false fits.
  // The box turned by its faces' lines (refine_box_theta) stands only when it explains
  // the points better than the box of the normals alone: faces assigned by noisy normals
  // can pull the lines off (a box cut by the border, far away).
  // The lines are fitted only when the normals' azimuth is in doubt: when two of its
  // standard errors turn the footprint's corners by more than box_azimuth_doubt_m.
  const Candidate box = [&] {
    const BoxAzimuth azimuth = box_azimuth(s);
    Candidate by_normals = fit_box(s, params, azimuth);
    if (azimuth.sides.empty() ||
        2 * std::sqrt(azimuth.theta_variance) * azimuth.half_diagonal <= params.box_azimuth_doubt_m)
      return by_normals;
    const double theta_lines = refine_box_theta(s, azimuth.sides, azimuth.theta);
    if (std::abs(theta_lines - azimuth.theta) < 1e-9) return by_normals;
    Candidate by_lines = box_at(s, params, theta_lines, azimuth.sides);
    if (!by_lines.valid) return by_normals;
    if (!by_normals.valid) return by_lines;
    evaluate(by_normals, s);
    evaluate(by_lines, s);
    return by_lines.score > by_normals.score ? by_lines : by_normals;
  }();
  const double width = box.valid ? 2 * box.ex : 0;
  double footprint_span = -1;  // points_span(s), measured when a radius passes the box's width
  const Candidate cyl = fit_cylinder(s, all, 0.0, params, rng);
  cands.push_back(cyl);
  cands.push_back(fit_cone(s, all, cyl, params));
  if (!box.valid || (s.top > 0.5 * width && s.top < params.sphere_max_top_over_width * width))
    cands.push_back(fit_sphere(s, params));
  if (!box.valid || s.bulk_top < 0.55 * width) cands.push_back(fit_torus(s, cyl, params));
  cands.push_back(box);
  // A cylinder lying on the support along either side of the box's footprint: along its
  // length (a bottle, a rolling pin) or across it (a tin on its side, shorter than wide).
  struct {
    double value = -1;  // independent_points(s), counted once when first needed
  } independent;
  bool lying_shown = false;  // a lying cylinder whose normals show it (nearer_than_box_faces)
  std::vector<double> box_misfits;  // the box's normal_misfits, asked with `independent`
  if (box.valid)
    for (const double along : {box.theta, box.theta + kPi / 2}) {
      if (!round_across(s, along)) continue;
      Candidate lying =
          fit_lying_cylinder_along(s, along, box.ca, box.cb, std::max(0.005, s.top / 2), params);
      if (lying.valid && independent.value < 0) {
        box_misfits = normal_misfits(box, s);
        independent.value = independent_points(s, params.focal_px);
      }
      lying.valid = lying.valid && nearer_than_box_faces(lying, box_misfits, s, independent.value);
      lying_shown = lying_shown || lying.valid;
      cands.push_back(lying);
    }

  // Flat sides show as side normals bunched into at most two azimuths 90 degrees
  // apart (|mean of 4x azimuth| near 1); a round side spreads them (near 0).
  const double flatness =
      normals_flatness(s, [&](size_t i) -> std::optional<std::array<double, 2>> {
        if (std::abs(s.up[i]) > 0.4) return std::nullopt;
        return std::array<double, 2>{s.na[i], s.nb[i]};
      });
  // The score is in units of the tolerance, which grows with sigma_z: a margin that is
  // a share of it asks a far object for a residual gain many times larger in
  // millimetres than a near one (at 2 m, 13x that at 1 m), while the shapes differ by
  // the same millimetres. The margins hold where the tolerance is at most its value at
  // 1 m and shrink with its square beyond.
  double mean_tol = 0;
  for (double t : s.tol) mean_tol += t;
  mean_tol /= static_cast<double>(s.tol.size());
  const double tol_1m =
      std::max(params.min_tolerance_m, params.noise_factor * params.depth_noise.sigma_z(1.0));
  const double margin_scale = std::min(1.0, (tol_1m / mean_tol) * (tol_1m / mean_tol));
  const double complexity_margin = params.complexity_margin * margin_scale;
  // Each candidate is judged once: bounds, fit to the points, frustum or cylinder; its
  // evidence is the score less the side-shape penalty, its rank that less the margin
  // the more complex shapes pay.
  std::vector<double> evidence, rank;
  std::vector<char> judged;
  auto judge = [&](size_t i) {
    evidence.resize(cands.size(), 0);
    rank.resize(cands.size(), 0);
    judged.resize(cands.size(), 0);
    Candidate& c = cands[i];
    // A radius far beyond the footprint, wider than the whole of it, is a flat face read
    // as a huge arc (an arc seen over less than 60 degrees).
    const double radius = std::max(c.r0, c.r1);
    if (box.valid && (c.model == Model::cylinder || c.model == Model::cone) &&
        radius > std::max(width, 0.03)) {
      if (footprint_span < 0) footprint_span = points_span(s);
      if (radius > std::max(footprint_span, 0.03)) c.valid = false;
    }
    if (!c.valid) return;
    settle_inner_floor(c, s);
    evaluate(c, s);
    settle_frustum(c, s, 2 * complexity_margin);
    out.candidates.push_back(to_fit(c, frame));
    // Cones and tori have more freedom than the shapes they generalise: they must
    // explain clearly more to win.
    const double margin = (c.model == Model::cone || c.model == Model::torus ||
                           c.model == Model::lying_cylinder)
                              ? complexity_margin
                              : 0.0;
    double score = c.score;
    const bool round = c.model == Model::cylinder || c.model == Model::cone;
    if (flatness > 0.6 && round) score -= params.side_shape_penalty;
    // A box pays where the normals sweep round: an upright side's round its vertical
    // axis, or a lying cylinder's round its level one (nearer_than_box_faces).
    if (((flatness >= 0 && flatness < kRoundSides) || lying_shown) && c.model == Model::box)
      score -= params.side_shape_penalty;
    evidence[i] = score;
    rank[i] = score - margin;
    judged[i] = 1;
  };
  // The best judged candidate by rank; far away, where coverage saturates and the
  // choice rests on residuals a few millimetres apart, the size of the noise, and a
  // shape with more parameters follows the noise better by chance: among the saturated
  // candidates the one with the least Bayesian information criterion, the residual in
  // units of the noise (estimated by the closest fit's RMS, an upper bound of it)
  // against the parameters it fitted (saturated_choice).
  double tol2 = 0;
  for (double t : s.tol) tol2 += t * t;
  tol2 /= static_cast<double>(s.tol.size());
  // Only a candidate explaining min_coverage of the points can be the shape, when one
  // does: a tighter fit of fewer points can rank above it, and the object would then be
  // `unknown` (the real milk frame's detergent bottle: a cylinder of 52 % ranked above
  // one of 65 % once its floor's plane moved by 0.1 degree).
  auto choose = [&](int& best, double& best_score) {
    best = -1;
    best_score = -1;
    for (const bool covering : {true, false}) {
      for (size_t i = 0; i < cands.size(); ++i)
        if (judged[i] && cands[i].valid && rank[i] > best_score &&
            (!covering || cands[i].coverage >= params.min_coverage)) {
          best_score = rank[i];
          best = static_cast<int>(i);
        }
      if (best >= 0) break;
    }
    if (best < 0) return;
    best = credited_rival(cands, rank, judged, best);
    best_score = rank[best];
    if (cands[best].coverage < 1 - params.complexity_margin) {
      // A saturated candidate behind the best only by the margin it paid
      // (margin_paid_choice).
      std::vector<SelectionEntry> entries{
          {evidence[best], cands[best].coverage, cands[best].rms, parameter_count(cands[best].model)}};
      std::vector<int> index{best};
      for (size_t i = 0; i < cands.size(); ++i)
        if (judged[i] && cands[i].valid && cands[i].coverage >= 1 - params.complexity_margin &&
            rank[i] < evidence[i] && evidence[i] > evidence[best]) {
          entries.push_back({evidence[i], cands[i].coverage, cands[i].rms, parameter_count(cands[i].model)});
          index.push_back(static_cast<int>(i));
        }
      if (index.size() < 2) return;
      if (independent.value < 0) independent.value = independent_points(s, params.focal_px);
      best = index[static_cast<size_t>(margin_paid_choice(entries, independent.value, tol2,
                                                          1 - params.complexity_margin))];
      return;
    }
    std::vector<SelectionEntry> entries;
    std::vector<int> index;
    int saturated = 0;
    for (size_t i = 0; i < cands.size(); ++i)
      if (judged[i] && cands[i].valid) {
        entries.push_back({evidence[i], cands[i].coverage, cands[i].rms, parameter_count(cands[i].model)});
        index.push_back(static_cast<int>(i));
        saturated += cands[i].coverage >= 1 - params.complexity_margin;
      }
    if (saturated < 2) return;  // nothing to choose between
    if (independent.value < 0) independent.value = independent_points(s, params.focal_px);
    const int pick = saturated_choice(entries, independent.value, tol2, 1 - params.complexity_margin);
    if (pick >= 0) best = index[static_cast<size_t>(pick)];
  };
  for (size_t i = 0; i < cands.size(); ++i) judge(i);
  int best = -1;
  double best_score = -1;
  choose(best, best_score);
  // A box wins on a flat top seen from above (it explains a disc as its top face and
  // whatever is below as inside it), but a box's top outline is a rectangle: when the
  // footprint's outline is round, the object is round (a bowl or a lampshade widening
  // up, whose side hides under its rim; a can). Its circle gives an upright cylinder,
  // and the cone from it, in the box's place.
  if (best >= 0 && cands[best].model == Model::box && s.has_normals) {
    int top_seen = 0;
    for (size_t i = 0; i < s.p.size(); ++i) top_seen += s.up[i] > 0.9 && s.p[i].h > s.top - std::max(0.02, 0.15 * s.top);
    Circle rim;
    const double roundness = top_seen >= 30 ? footprint_round_over_rectangle(s, cands[best], params, rim) : 0;
    if (top_seen >= 30 && top_seen >= 0.3 * s.p.size() &&
        roundness >= params.min_footprint_roundness) {
      Candidate round_top;
      round_top.model = Model::cylinder;
      round_top.ca = rim.x;
      round_top.cb = rim.y;
      round_top.r0 = round_top.r1 = rim.r;
      round_top.h0 = 0;
      round_top.h1 = cands[best].h1;
      round_top.valid = rim.r >= params.min_radius_m && rim.r <= params.max_radius_m;
      if (round_top.valid) {
        const int box_index = best;
        cands.push_back(round_top);
        cands.push_back(fit_cone(s, all, round_top, params));
        judge(cands.size() - 2);
        judge(cands.size() - 1);
        cands[static_cast<size_t>(box_index)].valid = false;
        choose(best, best_score);
        if (best < 0 || cands[best].coverage < params.min_coverage) {
          cands[static_cast<size_t>(box_index)].valid = true;
          choose(best, best_score);
        }
      }
    }
  }
  // An upright cylinder whose side does not show where it would face the camera
  // narrows under its rim (frustum_under_rim): the frustum that hides it, when it
  // explains the points as well.
  if (best >= 0 && cands[best].model == Model::cylinder) {
    const double sampled = static_cast<double>(s.p.size()) / static_cast<double>(points.size());
    if (std::optional<Candidate> bowl = frustum_under_rim(s, cands[best], sampled, params)) {
      evaluate(*bowl, s);
      if (bowl->coverage >= cands[best].coverage - params.complexity_margin) {
        out.candidates.push_back(to_fit(*bowl, frame));
        cands.push_back(*bowl);
        best = static_cast<int>(cands.size()) - 1;
      }
    }
  }
  // A solid cannot be seen through (min_foot_seen_pixels): the best cylinder, cone or box
  // through which the support's surface was seen gives way, a cylinder to the frustum on
  // the foot that surface leaves free, else to the next shape. When no shape is left
  // that covers min_coverage, the first stands: the surface is then no floor of the
  // object's.
  if (!s.ground.empty() && best >= 0) {
    const int first = best;
    const double least = std::max(
        static_cast<double>(params.min_foot_seen_pixels),
        params.min_foot_seen_share * static_cast<double>(around.object_pixels > 0
                                                             ? around.object_pixels
                                                             : static_cast<int>(points.size())));
    std::vector<int> contradicted;
    while (best >= 0) {
      const Candidate seen = cands[static_cast<size_t>(best)];
      const std::vector<double> radii = seen_through_radii(s, seen, params);
      if (static_cast<double>(radii.size()) * s.ground_pixels < least) break;
      cands[static_cast<size_t>(best)].valid = false;
      contradicted.push_back(best);
      // The frustum stands when it explains the points as well as the cylinder did (as
      // frustum_under_rim's): the points alone cannot tell the two apart.
      if (seen.model == Model::cylinder)
        if (std::optional<Candidate> cup = frustum_on_free_foot(seen, radii, params)) {
          cands.push_back(*cup);
          judge(cands.size() - 1);
          if (cands.back().valid &&
              cands.back().coverage >= seen.coverage - params.complexity_margin) {
            best = static_cast<int>(cands.size()) - 1;
            best_score = rank.back();
            continue;
          }
        }
      choose(best, best_score);
    }
    if (best < 0 || cands[static_cast<size_t>(best)].coverage < params.min_coverage) {
      for (int i : contradicted) cands[static_cast<size_t>(i)].valid = true;
      best = first;
      best_score = rank[static_cast<size_t>(first)];
    }
  }
  // Far away the tolerance (noise_factor x sigma_z) grows until a shape and its rival
  // both explain every point: coverage no longer tells them apart, the residuals do.
  // A cylinder in any orientation must then fit about as closely as the best upright
  // shape, within the spread an RMS of n noisy points has (far boxes were tins on edge).
  auto as_close = [&](const ShapeFit& fit) {
    const bool rival_ok = best >= 0 && cands[best].coverage >= params.min_coverage;
    const bool saturated = rival_ok && cands[best].coverage >= 1 - params.complexity_margin &&
                           fit.coverage >= 1 - params.complexity_margin;
    const double spread = 1 + 2 / std::sqrt(static_cast<double>(s.p.size()));
    return !saturated || fit.rms_m <= spread * cands[best].rms;
  };
  // A cylinder lying on its side or leaning (cylinder_any_axis.h): it wins when it
  // explains clearly more than the best shape standing upright and its side normals
  // sweep round its axis rather than bunch into a box's faces.
  // Only fits that could be chosen are finished (AxisGate): a cylinder whose axis is
  // not lying (resp. not on its rim) is never chosen, nor one whose score (at most 1,
  // the share of points it explains) cannot pass `beat`; such fits are left out of the
  // candidates too.
  std::optional<ShapeFit> any_axis;
  const AxisGate lying_axis = [&](Vec3 axis) { return std::abs(dot(axis, frame.n)) < std::cos(kPi / 4); };
  const double beat = best >= 0 ? best_score + params.complexity_margin : 0.0;
  if (s.has_normals && beat < 1) {
    std::vector<Vec3> n3(s.p.size());
    for (size_t i = 0; i < s.p.size(); ++i) n3[i] = frame.dir(s.na[i], s.nb[i], s.up[i]);
    AxisCylinderFit any = fit_cylinder_any_axis(s.xyz, n3, s.tol, params, lying_axis);
    if (any.valid) {
      out.candidates.push_back(any.fit);
      const bool lying = lying_axis(any.fit.primitive.axis);
      // A lying cylinder whose solid passes through the support it rests on is not what
      // lies there (nyu_basement's bin: r 0.32 m, its centre at the floor's height; a
      // bottle seen from above, its axis tilted into the table): refitted resting on
      // the plane (resting_lying_cylinder), and judged as that.
      if (lying) {
        if (std::optional<Candidate> rest = resting_lying_cylinder(s, any.fit, frame, params)) {
          any.fit = to_fit(*rest, frame);
          any.score = rest->score;
          out.candidates.push_back(any.fit);
        }
      }
      if (lying && any.facetedness < params.max_round_facetedness &&
          any.fit.coverage >= params.min_coverage && any.score > beat && as_close(any.fit))
        any_axis = any.fit;
    }
  }
  // A short wide cylinder on its rim (a tin on its edge, lid to the camera) is what a box
  // would explain too; its outline seen along its axis is a circle, not a rectangle.
  const bool box_wins = best < 0 || cands[best].coverage < params.min_coverage ||
                        cands[best].model == Model::box;
  if (!any_axis && box_wins) {
    const DiscCylinderFit disc = fit_cylinder_on_rim(s.xyz, s.tol, params, lying_axis);
    if (disc.cylinder.valid) {
      out.candidates.push_back(disc.cylinder.fit);
      const bool on_rim = lying_axis(disc.cylinder.fit.primitive.axis);
      const double rival = best >= 0 && cands[best].coverage >= params.min_coverage ? cands[best].coverage : 0.0;
      if (on_rim && disc.round_outline >= params.min_round_outline &&
          disc_round_over_rectangle(s, disc.cylinder.fit.primitive.axis, params) >= kRoundOverRectangle &&
          disc.cylinder.fit.coverage >= params.min_coverage &&
          disc.cylinder.fit.coverage >= rival - params.complexity_margin && as_close(disc.cylinder.fit))
        any_axis = disc.cylinder.fit;
    }
  }
  if (any_axis) {
    out.primitives.push_back(*any_axis);
    out.fit = any_axis->coverage;
    return out;
  }
  // Secondary primitive: the points above an upright body that it does not explain
  // (a bottle's shoulder and neck), fitted as a cone or cylinder over that band; with the
  // share of the points they are.
  struct Secondary {
    Candidate neck;
    double share = 0;
    std::vector<int> rest;  // its points, from `base` up (neck_top_radius)
    double base = 0;
  };
  auto secondary_candidate = [&](const Candidate& body,
                                 double min_share) -> std::optional<Secondary> {
    if (body.model != Model::cylinder && body.model != Model::box) return std::nullopt;
    std::vector<int> rest;
    const CandidateTerms body_terms = terms_of(body);
    for (size_t i = 0; i < s.p.size(); ++i)
      if (distance(body, body_terms, s.p[i]) > s.tol[i] && s.p[i].h > body.h1 - 2 * s.tol[i])
        rest.push_back(static_cast<int>(i));
    const double share = static_cast<double>(rest.size()) / s.p.size();
    if (share < min_share || rest.size() < 30) return std::nullopt;
    std::vector<double> rh;
    for (int i : rest) rh.push_back(s.p[i].h);
    const double base = quantile(rh, 0.02);
    Candidate neck = fit_cylinder(s, rest, base, params, rng);
    Candidate cone = fit_cone(s, rest, neck, params);
    Samples sub;
    sub.has_normals = s.has_normals;
    for (int i : rest) {
      sub.p.push_back(s.p[i]);
      sub.tol.push_back(s.tol[i]);
      sub.up.push_back(s.up[i]);
    }
    Candidate* pick = nullptr;
    if (neck.valid) {
      evaluate(neck, sub);
      pick = &neck;
    }
    if (cone.valid) {
      evaluate(cone, sub);
      settle_frustum(cone, sub, params.complexity_margin);
      if (!pick || cone.score - params.complexity_margin > pick->score) pick = &cone;
    }
    if (!pick || pick->coverage < 0.6) return std::nullopt;
    // A neck is a real part: taller than a lid's rim and no wider than the body.
    const double body_r = body.model == Model::cylinder ? body.r0 : std::max(body.ex, body.ey);
    if (pick->h1 - pick->h0 < 0.015 || std::max(pick->r0, pick->r1) > 1.05 * body_r)
      return std::nullopt;
    return Secondary{*pick, share, std::move(rest), base};
  };
  auto secondary_fit = [&](const Secondary& second) {
    ShapeFit fit = to_fit(second.neck, frame);
    fit.coverage = second.neck.coverage * second.share;
    fit.primitive.fit = fit.coverage;
    return fit;
  };
  // A neck narrows to a share of the body (a bowl's flared rim above the cylinder of its
  // foot is no neck): the narrower of its fit and its upper part's circle (measured only
  // when the fit is not narrow enough).
  auto narrow_neck = [&](const Secondary& second, const Candidate& body) {
    const double most = params.pair_max_neck_share * body.r0;
    if (std::min(second.neck.r0, second.neck.r1) <= most) return true;
    const double top = neck_top_radius(s, second.rest, second.base, params);
    return top > 0 && top <= most;
  };
  auto secondary = [&](const Candidate& body) -> std::optional<ShapeFit> {
    const std::optional<Secondary> second = secondary_candidate(body, params.min_secondary_share);
    if (!second) return std::nullopt;
    return secondary_fit(*second);
  };

  std::optional<ShapeFit> second;
  // A body cylinder plus a neck can explain a bottle better than one cone through
  // both: prefer the pair when it covers clearly more. Their coverages are shares of the
  // points, which may count a point twice: the pair covers at most all of them, so a
  // cone explaining every point keeps it (fresh rooms 9882: a bowl 2.4 m away, its
  // cylinder 86 % and its rim as a "neck" 23 %, against the cone's 100 %).
  // Far away both cover every point (the tolerance grows with the noise): the residuals
  // decide, by the information criterion over the two (pair_over_cone).
  if (best >= 0 && cands[best].model == Model::cone && cands[0].valid &&
      cands[0].model == Model::cylinder) {
    const std::optional<Secondary> neck =
        secondary_candidate(cands[0], params.pair_min_secondary_share);
    if (neck) {
      const ShapeFit neck_fit = secondary_fit(*neck);
      const bool covers_more = neck->share >= params.min_secondary_share &&
                               std::min(1.0, cands[0].coverage + neck_fit.coverage) >
                                   cands[best].coverage + 2 * params.complexity_margin;
      const double saturated = 1 - params.complexity_margin;
      const auto explains_closer = [&] {
        if (!narrow_neck(*neck, cands[0])) return false;
        if (independent.value < 0) independent.value = independent_points(s, params.focal_px);
        return pair_over_cone(s, cands[0], neck->neck, cands[best], independent.value, tol2,
                              saturated);
      };
      if (covers_more || (cands[best].coverage >= saturated && explains_closer())) {
        best = 0;
        second = neck_fit;
      }
    }
  }
  // A bottle's body alone may explain too little (its shoulder and neck a third of its
  // height or more): the body with a narrow neck is the shape when the two together
  // cover min_coverage and the body half of the points.
  bool with_neck_covers = false;
  if ((best < 0 || cands[best].coverage < params.min_coverage) && cands[0].valid &&
      cands[0].model == Model::cylinder && cands[0].coverage >= kBodyLeastShare) {
    const std::optional<Secondary> neck = secondary_candidate(cands[0], params.min_secondary_share);
    if (neck && narrow_neck(*neck, cands[0])) {
      const ShapeFit neck_fit = secondary_fit(*neck);
      if (cands[0].coverage + neck_fit.coverage >= params.min_coverage) {
        best = 0;
        second = neck_fit;
        with_neck_covers = true;
      }
    }
  }
  if (!with_neck_covers && (best < 0 || cands[best].coverage < params.min_coverage)) {
    const ShapeFit tilted = fit_oriented_box(s, params);
    if (!tilted.primitive.dimensions_m.empty()) {
      out.candidates.push_back(tilted);
      if (tilted.coverage >= params.min_coverage) {
        out.primitives.push_back(tilted);
        out.fit = tilted.coverage;
        out.depth_unseen = params.one_face_box_partial && one_face_thick(tilted, s);
      }
    }
    return out;
  }
  const Candidate& salient = cands[best];
  out.primitives.push_back(to_fit(salient, frame));
  out.depth_unseen = salient.model == Model::box && salient.depth_unseen;
  out.fit = salient.coverage;
  if (!second) second = secondary(salient);
  if (second) out.primitives.push_back(*second);
  return out;
}

bool within_shape(const ShapeFit& fit, Vec3 p, double margin) {
  const PhysicalPrimitive& prim = fit.primitive;
  const auto& d = prim.dimensions_m;
  const Vec3 a = normalized(prim.axis);
  const Vec3 q = p - prim.center;
  const double along = dot(q, a);
  const Vec3 across = q - a * along;
  switch (prim.kind) {
    case ShapeKind::sphere:
      return d.size() >= 1 && norm(q) <= d[0] + margin;
    case ShapeKind::cylinder:
    case ShapeKind::cone:
      return d.size() >= 2 && norm(across) <= d[0] + margin && std::abs(along) <= d[1] / 2 + margin;
    case ShapeKind::torus:
      return d.size() >= 2 && norm(across) <= d[0] + d[1] + margin &&
             std::abs(along) <= d[1] + margin;
    case ShapeKind::box: {
      if (d.size() < 3) return false;
      const Vec3 u = normalized(fit.x_axis - a * dot(fit.x_axis, a));
      const Vec3 v = cross(a, u);
      return std::abs(dot(q, u)) <= d[0] / 2 + margin && std::abs(dot(q, v)) <= d[1] / 2 + margin &&
             std::abs(along) <= d[2] / 2 + margin;
    }
    case ShapeKind::plane: return false;  // not a solid: holds no part of an object
  }
  return false;
}

}  // namespace annex
