// Touching bodies one primitive explains poorly, cut in two (touching_split.h).
#include "touching_split.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>

#include "annex/runtime/object_shape_recognizer.h"
#include "quantile.h"

namespace annex {
namespace {

constexpr double kPi = 3.14159265358979323846;

// What the criterion needs of one fitted cluster.
struct FitTerms {
  double pixels = 0;     // full-resolution pixels
  double depth = 0;      // their mean depth
  double focal_px = 0;   // the frame's: a pixel's footprint at that depth is depth / focal_px
  DepthNoise noise;      // the camera's (ShapeRecognizerParams::depth_noise)
  double coverage = 0, rms = 0;
  int parameters = 0;
  bool recognised = false;
  bool level_cylinder = false;  // a cylinder lying on its side (kLevelAxisCos)
};

// A cylinder whose axis lies within about 10 degrees of level lies on its side.
constexpr double kLevelAxisCos = 0.17;

// The shape a cluster was given, or when unknown its best candidate (it still explains
// part of the points); null when none was tried.
const ShapeFit* fit_of(const ScanCluster& c) {
  if (!c.shape.primitives.empty()) return &c.shape.primitives.front();
  const ShapeFit* best = nullptr;
  for (const ShapeFit& k : c.shape.candidates)
    if (!best || k.coverage > best->coverage) best = &k;
  return best;
}

FitTerms terms_of(const Frame& f, const ScanCluster& c, const DepthNoise& noise) {
  FitTerms t;
  double z = 0;
  int n = 0;
  for (int i : c.pixels)
    if (has_depth(f.points[static_cast<size_t>(i)])) {
      z += f.points[static_cast<size_t>(i)].z;
      ++n;
    }
  t.pixels = n;
  t.depth = n > 0 ? z / n : 1;
  t.focal_px = focal_px(f);
  t.noise = noise;
  t.recognised = !c.shape.primitives.empty();
  if (const ShapeFit* fit = fit_of(c)) {
    t.coverage = fit->coverage;
    t.rms = fit->rms_m;
    t.parameters = fitted_parameter_count(*fit, c.support);
    t.level_cylinder = fit->primitive.kind == ShapeKind::cylinder &&
                       std::abs(dot(normalized(fit->primitive.axis), normalized(c.support.normal))) <
                           kLevelAxisCos;
  }
  return t;
}

// The independent noise samples among a cluster's pixels: a pixel counts its own area
// over that of the neighbourhood it shares its noise with (shared_noise_radius_m; the
// recognizer's independent_points).
double independent(const FitTerms& t) {
  const double z = t.depth, pixel = z / t.focal_px;
  const double r = shared_noise_radius_m(z, t.focal_px, t.noise);
  return std::max(1.0, t.pixels * pixel * pixel / (kPi * r * r));
}

// The mean squared residual per point in units of the axial noise: explained points
// at the fit's RMS, the others at least at the fit's tolerance.
double residual_energy(const FitTerms& t, const ShapeRecognizerParams& shape) {
  const double sigma = t.noise.sigma_z(t.depth);
  const double tol = std::max(shape.min_tolerance_m, shape.noise_factor * sigma);
  return t.coverage * (t.rms / sigma) * (t.rms / sigma) + (1 - t.coverage) * (tol / sigma) * (tol / sigma);
}

// The two means' cut of a cluster's footprint: each pixel's side, the footprint's points
// on the support (e1, e2) and the two means.
struct MeansCut {
  std::vector<char> side;
  std::vector<std::array<double, 2>> q;
  std::array<double, 2> m0{}, m1{};
};

// The pixels a body of the given size shows at depth z: the disc it spans in the image.
int min_part_pixels(double size_m, double z, double focal_px) {
  const double across_px = size_m * focal_px / std::max(z, 0.1);
  return static_cast<int>(std::ceil(kPi / 4 * across_px * across_px));
}

// The cluster's pixels in two by two means of their footprint on the support, started
// at the ends of its long axis; no side when either part is too small (under min_share
// of the pixels or min_points).
MeansCut two_means(const Frame& f, const ScanCluster& c, double min_share, int min_points) {
  const Vec3 n = c.support.normal;
  const Vec3 seed = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = normalized(cross(n, seed)), e2 = cross(n, e1);
  MeansCut cut;
  std::vector<std::array<double, 2>>& q = cut.q;
  q.reserve(c.pixels.size());
  double ma = 0, mb = 0;
  for (int i : c.pixels) {
    const PointXYZRGB& p = f.points[static_cast<size_t>(i)];
    const Vec3 v{p.x, p.y, p.z};
    q.push_back({dot(v, e1), dot(v, e2)});
    ma += q.back()[0];
    mb += q.back()[1];
  }
  if (q.size() < 2) return {};
  ma /= static_cast<double>(q.size());
  mb /= static_cast<double>(q.size());
  double saa = 0, sab = 0, sbb = 0;
  for (const auto& p : q) {
    saa += (p[0] - ma) * (p[0] - ma);
    sab += (p[0] - ma) * (p[1] - mb);
    sbb += (p[1] - mb) * (p[1] - mb);
  }
  const double n_q = static_cast<double>(q.size());
  saa /= n_q, sab /= n_q, sbb /= n_q;
  // The long axis: the covariance's larger eigenvector.
  const double tr = saa + sbb, det = saa * sbb - sab * sab;
  const double l1 = tr / 2 + std::sqrt(std::max(0.0, tr * tr / 4 - det));
  double ax = std::abs(sab) > 1e-15 ? l1 - sbb : (saa >= sbb ? 1 : 0), ay = std::abs(sab) > 1e-15 ? sab : (saa >= sbb ? 0 : 1);
  const double len = std::sqrt(ax * ax + ay * ay);
  if (len <= 0 || l1 <= 0) return {};
  ax /= len, ay /= len;
  const double sd = std::sqrt(l1);
  std::array<double, 2>&m0 = cut.m0, &m1 = cut.m1;
  m0 = {ma - sd * ax, mb - sd * ay}, m1 = {ma + sd * ax, mb + sd * ay};
  // The means from an even subsample of at most kMeanPoints pixels (a mean of a few
  // thousand moves by a fraction of a millimetre), then every pixel to the nearer.
  constexpr size_t kMeanPoints = 2000;
  const size_t stride = std::max<size_t>(1, q.size() / kMeanPoints);
  auto nearer_second = [&](const std::array<double, 2>& p) {
    return std::pow(p[0] - m1[0], 2) + std::pow(p[1] - m1[1], 2) <
           std::pow(p[0] - m0[0], 2) + std::pow(p[1] - m0[1], 2);
  };
  for (int it = 0; it < 10; ++it) {
    double s0a = 0, s0b = 0, s1a = 0, s1b = 0;
    int n0 = 0, n1 = 0;
    for (size_t k = 0; k < q.size(); k += stride) {
      if (nearer_second(q[k])) {
        s1a += q[k][0], s1b += q[k][1], ++n1;
      } else {
        s0a += q[k][0], s0b += q[k][1], ++n0;
      }
    }
    if (n0 == 0 || n1 == 0) return {};
    m0 = {s0a / n0, s0b / n0};
    m1 = {s1a / n1, s1b / n1};
  }
  std::vector<char> side(q.size(), 0);
  for (size_t k = 0; k < q.size(); ++k) side[k] = nearer_second(q[k]);
  const auto ones = static_cast<double>(std::count(side.begin(), side.end(), 1));
  if (std::min(ones, n_q - ones) < std::max(min_share * n_q, static_cast<double>(min_points))) return cut;
  cut.side = std::move(side);
  return cut;
}

// Distance from p to the surface of a fitted primitive (its solid's boundary).
double surface_distance(const ShapeFit& fit, Vec3 p) {
  const PhysicalPrimitive& q = fit.primitive;
  const Vec3 d = p - q.center;
  const double t = dot(d, q.axis);
  const double rho = norm(d - q.axis * t);
  const auto dim = [&](size_t k) { return k < q.dimensions_m.size() ? q.dimensions_m[k] : 0.0; };
  // A solid of revolution whose radius runs from r_lo at t = -h to r_hi at t = +h.
  const auto revolved = [&](double r_lo, double r_hi, double h) {
    const double r_at = r_lo + (r_hi - r_lo) * (std::clamp(t, -h, h) + h) / std::max(2 * h, 1e-9);
    const double out_r = rho - r_at, out_t = std::abs(t) - h;
    if (out_r <= 0 && out_t <= 0) return std::min(-out_r, -out_t);
    return std::sqrt(std::pow(std::max(out_r, 0.0), 2) + std::pow(std::max(out_t, 0.0), 2));
  };
  switch (q.kind) {
    case ShapeKind::sphere: return std::abs(norm(d) - dim(0));
    case ShapeKind::cylinder: return revolved(dim(0), dim(0), dim(1) / 2);
    case ShapeKind::cone: return revolved(dim(0), q.narrow_radius_m, dim(1) / 2);
    case ShapeKind::torus: return std::abs(std::hypot(rho - dim(0), t) - dim(1));
    case ShapeKind::box: {
      const Vec3 y = cross(q.axis, fit.x_axis);
      const double o[3] = {std::abs(dot(d, fit.x_axis)) - dim(0) / 2, std::abs(dot(d, y)) - dim(1) / 2,
                           std::abs(t) - dim(2) / 2};
      if (o[0] <= 0 && o[1] <= 0 && o[2] <= 0) return -std::max({o[0], o[1], o[2]});
      return std::sqrt(std::pow(std::max(o[0], 0.0), 2) + std::pow(std::max(o[1], 0.0), 2) +
                       std::pow(std::max(o[2], 0.0), 2));
    }
    case ShapeKind::plane: return std::abs(t);
  }
  return 1e9;
}

// The radius of a fitted primitive's footprint on its support (shape.h).
double footprint_radius(const ShapeFit& fit) {
  return annex::footprint_radius(fit.primitive.kind, fit.primitive.dimensions_m);
}

// Whether the fit leaves pixel p out: farther from its surface than the tolerance at p's
// depth.
bool left_out_by(const ShapeFit& fit, const PointXYZRGB& p, const ShapeRecognizerParams& shape) {
  const double tol =
      std::max(shape.min_tolerance_m, shape.noise_factor * shape.depth_noise.sigma_z(p.z));
  return surface_distance(fit, Vec3{p.x, p.y, p.z}) > tol;
}

// Whether what the cluster's shape leaves out lies on one side of the cut: one primitive
// over two bodies explains one and leaves the other out (at least two thirds of the
// pixels it leaves out on one side), while one object's misfit (a carton's open flaps,
// a wall's waviness) spreads along it. Only then is the cut worth its two fits.
bool misfit_on_one_side(const Frame& f, const ScanCluster& c, const std::vector<char>& side,
                        const ShapeRecognizerParams& shape) {
  const ShapeFit* fit = fit_of(c);
  if (!fit) return true;
  double out[2] = {0, 0};
  const size_t stride = std::max<size_t>(1, side.size() / 2000);  // an even subsample
  for (size_t k = 0; k < side.size(); k += stride) {
    out[side[k] ? 1 : 0] += left_out_by(*fit, f.points[static_cast<size_t>(c.pixels[k])], shape);
  }
  return 3 * std::max(out[0], out[1]) >= 2 * (out[0] + out[1]);
}

// Whether the footprint narrows between the two means. Across the line through two of
// its points, the width of a convex body's footprint is a concave function along it (no
// narrower between them than at the narrower end), so a width between the means under
// waist_share of that at the narrower mean is where two bodies meet: two balls or tins
// of a size narrow to a point at their contact, whichever is explained (the misfit of
// a cylinder over both spreads along it). The footprint is cut in kWaistBins bins from
// one mean to the other, each mean's width the widest of the two bins beside it.
bool footprint_waist(const MeansCut& cut, double waist_share) {
  constexpr int kWaistBins = 16;
  const std::array<double, 2> u{cut.m1[0] - cut.m0[0], cut.m1[1] - cut.m0[1]};
  const double len2 = u[0] * u[0] + u[1] * u[1];
  if (!(len2 > 0)) return false;
  // Bins of 1/kWaistBins of the means' distance, one more beyond each mean.
  std::array<double, kWaistBins + 2> lo, hi;
  lo.fill(1e9), hi.fill(-1e9);
  const size_t stride = std::max<size_t>(1, cut.q.size() / 2000);  // an even subsample
  for (size_t k = 0; k < cut.q.size(); k += stride) {
    const double dx = cut.q[k][0] - cut.m0[0], dy = cut.q[k][1] - cut.m0[1];
    const double along = (dx * u[0] + dy * u[1]) / len2, across = (dy * u[0] - dx * u[1]) / std::sqrt(len2);
    const int b = static_cast<int>(std::floor((along + 1.0 / kWaistBins) * kWaistBins));
    if (b < 0 || b > kWaistBins + 1) continue;
    lo[static_cast<size_t>(b)] = std::min(lo[static_cast<size_t>(b)], across);
    hi[static_cast<size_t>(b)] = std::max(hi[static_cast<size_t>(b)], across);
  }
  const auto width = [&](int b) { return std::max(0.0, hi[static_cast<size_t>(b)] - lo[static_cast<size_t>(b)]); };
  const double ends = std::min(std::max(width(0), width(1)), std::max(width(kWaistBins), width(kWaistBins + 1)));
  double narrowest = 1e9;
  for (int b = 2; b < kWaistBins; ++b) narrowest = std::min(narrowest, width(b));
  return narrowest < waist_share * ends;
}

// Whether the footprint shows two fronts: its range from the camera (q is the camera
// frame's points on the support's axes, so the camera is at 0, 0) recedes between the two
// means by more than
// `depth` from its nearest on both sides (stands_on_two_feet), or the footprint is seen
// in two pieces: a run of empty bins between the means that its sampling does not
// explain. Bins as footprint_waist's. A far foot leaves single bins empty at random: a
// bin holding on average `lambda` points (those seen over the bins that hold any) is
// empty with probability exp(-lambda), so a run of r empty bins counts when
// lambda r >= gap_evidence (exp(-gap_evidence): the chance it is sampling's).
bool fronts_apart(const MeansCut& cut, double depth, double gap_evidence) {
  constexpr int kBins = 16;
  const std::array<double, 2> u{cut.m1[0] - cut.m0[0], cut.m1[1] - cut.m0[1]};
  const double len2 = u[0] * u[0] + u[1] * u[1];
  if (!(len2 > 0)) return false;
  std::array<double, kBins + 2> near;
  near.fill(1e9);
  size_t binned = 0;
  for (const auto& q : cut.q) {
    const double along = ((q[0] - cut.m0[0]) * u[0] + (q[1] - cut.m0[1]) * u[1]) / len2;
    const int b = static_cast<int>(std::floor((along + 1.0 / kBins) * kBins));
    if (b < 0 || b > kBins + 1) continue;
    near[static_cast<size_t>(b)] = std::min(near[static_cast<size_t>(b)], std::hypot(q[0], q[1]));
    ++binned;
  }
  // The nearest range from either end up to each bin.
  std::array<double, kBins + 2> from_m0 = near, from_m1 = near;
  for (size_t b = 1; b < near.size(); ++b) from_m0[b] = std::min(from_m0[b], from_m0[b - 1]);
  for (size_t b = near.size() - 1; b-- > 0;) from_m1[b] = std::min(from_m1[b], from_m1[b + 1]);
  for (size_t b = 2; b < kBins; ++b)
    if (near[b] < 1e9 && near[b] > from_m0[b - 1] + depth && near[b] > from_m1[b + 1] + depth)
      return true;
  if (gap_evidence <= 0) return false;
  const auto filled = std::count_if(near.begin(), near.end(), [](double r) { return r < 1e9; });
  const double lambda =
      static_cast<double>(binned) / static_cast<double>(std::max<std::ptrdiff_t>(1, filled));
  int run = 0;
  for (size_t b = 2; b < kBins; ++b) {
    run = near[b] < 1e9 ? 0 : run + 1;
    if (from_m0[b - 1] < 1e9 && from_m1[b + 1] < 1e9 && lambda * run >= gap_evidence) return true;
  }
  return false;
}

// Whether the cluster stands on two feet (stands_on_two_feet), given its two means.
bool two_feet(const Frame& f, const ScanCluster& c, const MeansCut& means, double depth_m,
              const TouchingSplitParams& params) {
  if (means.q.size() != c.pixels.size()) return false;
  std::vector<double> h(c.pixels.size());
  double top = 0, bottom = 1e9;
  for (size_t k = 0; k < c.pixels.size(); ++k) {
    const PointXYZRGB& p = f.points[static_cast<size_t>(c.pixels[k])];
    h[k] = dot(c.support.normal, Vec3{p.x, p.y, p.z}) + c.support.d;
    top = std::max(top, h[k]);
    bottom = std::min(bottom, h[k]);
  }
  MeansCut foot;
  foot.m0 = means.m0, foot.m1 = means.m1;
  for (size_t k = 0; k < h.size(); ++k)
    if (h[k] <= params.foot_share * top) foot.q.push_back(means.q[k]);
  // No foot seen, though the cluster reaches into its lower half: bodies seen from above
  // that hide their feet under their rims or bulges (a bowl, a ring lying flat). Nothing
  // tells one body from two, and the cut is tried. What is seen only higher up (a
  // shelf's board over the floor) does not stand there.
  if (foot.q.empty()) return bottom < 0.5 * top;
  return footprint_waist(foot, params.waist_share) &&
         fronts_apart(foot, params.notch_sigmas * params.depth_noise.sigma_z(depth_m),
                      params.gap_evidence);
}

// The criterion (touching_split.h) of a cut into parts a and b against the whole.
struct Criterion {
  double one = 0, two = 0;
};

Criterion criterion(const FitTerms& whole, const FitTerms& a, const FitTerms& b, const ShapeRecognizerParams& shape) {
  // Over the same independent points: one primitive against two and the cut (its
  // position and direction).
  const double n_a = independent(a), n_b = independent(b), n = n_a + n_b;
  const double ln = std::log(std::max(n, 2.0));
  return {n * residual_energy(whole, shape) + whole.parameters * ln,
          n_a * residual_energy(a, shape) + n_b * residual_energy(b, shape) + (a.parameters + b.parameters + 2) * ln};
}

// Both parts explained by their shapes over `least` of their points (a part explained
// worse is no body of its own: a wall's patch, a piece of furniture).
bool both_recognised(const FitTerms& a, const FitTerms& b, double least) {
  return a.recognised && b.recognised && a.coverage >= least && b.coverage >= least;
}

// The pixels the cluster's own shape leaves out, beyond its tolerance at their depth, as
// a cut's side (1): one primitive over two bodies explains one and leaves the other out.
std::vector<char> misfit_side(const Frame& f, const ScanCluster& c,
                              const ShapeRecognizerParams& shape) {
  const ShapeFit* fit = fit_of(c);
  if (!fit) return {};
  std::vector<char> side(c.pixels.size(), 0);
  for (size_t k = 0; k < side.size(); ++k)
    side[k] = left_out_by(*fit, f.points[static_cast<size_t>(c.pixels[k])], shape);
  return side;
}

// Whether the pixels `side` marks lie beside the cluster's primitive, as a second body
// does: their mean lies off its centre along the support by more than half its footprint's
// radius. What one object's primitive leaves out of it (its veil, a carton's flaps) lies
// round it (the milk frame's bleach bottle: 1.8 cm off).
bool beside_primitive(const Frame& f, const ScanCluster& c, const std::vector<char>& side) {
  const ShapeFit* fit = fit_of(c);
  if (!fit) return false;
  Vec3 sum{0, 0, 0};
  double count = 0;
  for (size_t k = 0; k < side.size(); ++k)
    if (side[k]) {
      const PointXYZRGB& p = f.points[static_cast<size_t>(c.pixels[k])];
      sum = sum + Vec3{p.x, p.y, p.z};
      ++count;
    }
  if (count == 0) return false;
  const Vec3 n = c.support.normal, off = sum * (1 / count) - fit->primitive.center;
  return norm(off - n * dot(n, off)) > 0.5 * footprint_radius(*fit);
}

// An upright primitive's axis lies within about 15 degrees of its support's normal.
constexpr double kUprightAxisCos = 0.966;

// Whether a fit is an upright cylinder, cone or box on a support of normal n: a solid
// whose outline across the line of sight is a straight line in height (width_step).
bool upright_solid(const PhysicalPrimitive& fit, Vec3 n) {
  return (fit.kind == ShapeKind::cylinder || fit.kind == ShapeKind::cone ||
          fit.kind == ShapeKind::box) &&
         std::abs(dot(normalized(fit.axis), n)) >= kUprightAxisCos;
}

// Parts a and b refitted (their normals into na, nb) with their criterion's terms; empty
// when either has no shape, or b's fails `keep_b` (when given). The second part first:
// along a misfit it is what the one primitive leaves out, often no body (a bottle's
// handle and veil on the milk frame), and the first part's refit is then not needed.
std::optional<std::pair<FitTerms, FitTerms>> refit_parts(
    const Frame& f, ScanCluster& a, ScanCluster& b, std::vector<Vec3>& na, std::vector<Vec3>& nb,
    const std::function<void(ScanCluster&, std::vector<Vec3>&)>& refit,
    const ShapeRecognizerParams& shape,
    const std::function<bool(const ScanCluster&, const FitTerms&)>& keep_b = {}) {
  refit(b, nb);
  const FitTerms tb = terms_of(f, b, shape.depth_noise);
  if (!tb.recognised || (keep_b && !keep_b(b, tb))) return std::nullopt;
  refit(a, na);
  const FitTerms ta = terms_of(f, a, shape.depth_noise);
  if (!ta.recognised) return std::nullopt;
  return std::pair{ta, tb};
}

// The cut of `cluster` along `side`, its parts refitted, then once more with each pixel
// given to the nearer of the two fitted surfaces; kept when both parts are explained and
// two primitives beat one by the criterion. `least`: the smaller part's fewest pixels.
std::optional<TouchingCut> refit_cut(
    const Frame& f, const ScanCluster& cluster, const std::vector<char>& side,
    const FitTerms& whole, double least,
    const std::function<void(ScanCluster&, std::vector<Vec3>&)>& refit,
    const ShapeRecognizerParams& shape, const TouchingSplitParams& params) {
  // The parts take no free-space test (ScanCluster::around): the support seen around
  // the whole is not what is seen around each, and the upper of two stacked bodies
  // stands on the lower.
  ScanCluster a, b;
  a.support = b.support = cluster.support;
  for (size_t k = 0; k < side.size(); ++k) (side[k] ? b : a).pixels.push_back(cluster.pixels[k]);
  std::vector<Vec3> na, nb;
  const std::optional<std::pair<FitTerms, FitTerms>> terms =
      refit_parts(f, a, b, na, nb, refit, shape);
  if (!terms) return std::nullopt;
  const auto& [ta, tb] = *terms;
  Criterion k = criterion(whole, ta, tb, shape);
  bool recognised = both_recognised(ta, tb, params.min_part_coverage);
  // The means' cut is straight; where the two bodies meet each pixel lies on one of
  // the two fitted surfaces: once more with each pixel given to the nearer. A part
  // holding a strip of the other body may be explained poorly by the straight cut alone
  // (rooms 9578: a box beside a ring lying flat, the box's part at 77 %, at 99 % once
  // the ring's strip is given back), so both parts need only a shape for this step.
  ScanCluster a2, b2;
  a2.support = b2.support = a.support;
  for (int i : cluster.pixels) {
    const PointXYZRGB& p = f.points[static_cast<size_t>(i)];
    const Vec3 v{p.x, p.y, p.z};
    const bool nearer_b = surface_distance(b.shape.primitives.front(), v) <
                          surface_distance(a.shape.primitives.front(), v);
    (nearer_b ? b2 : a2).pixels.push_back(i);
  }
  const auto smaller = static_cast<double>(std::min(a2.pixels.size(), b2.pixels.size()));
  if (smaller >= least && a2.pixels != a.pixels) {
    std::vector<Vec3> na2, nb2;
    refit(a2, na2);
    refit(b2, nb2);
    const FitTerms ta2 = terms_of(f, a2, shape.depth_noise),
                   tb2 = terms_of(f, b2, shape.depth_noise);
    const Criterion k2 = criterion(whole, ta2, tb2, shape);
    if (both_recognised(ta2, tb2, params.min_part_coverage) && (!recognised || k2.two < k.two)) {
      a = std::move(a2), b = std::move(b2), na = std::move(na2), nb = std::move(nb2);
      k = k2;
      recognised = true;
    }
  }
  if (!recognised || !(k.two < k.one)) return std::nullopt;
  // Two bodies stand side by side: their centres lie apart on the support by at least
  // half their footprints' radii together (touching, by the sum). One object's misfit,
  // refitted apart, gives two solids round one axis (rooms 5026's flat bowl at 0.98 m as a
  // cone and a cylinder, their centres 0.5 cm apart).
  const ShapeFit &fa = a.shape.primitives.front(), &fb = b.shape.primitives.front();
  const Vec3 n = cluster.support.normal, apart = fa.primitive.center - fb.primitive.center;
  if (norm(apart - n * dot(n, apart)) < 0.5 * (footprint_radius(fa) + footprint_radius(fb)))
    return std::nullopt;
  return TouchingCut{std::move(a), std::move(b), std::move(na), std::move(nb)};
}

// The cluster cut level at `cut` (a height over its support; `height` its pixels'),
// one body standing on the other: the parts refitted, kept when both are explained, two
// primitives beat one by the criterion and the upper stands over the lower's footprint.
// The upper part is fitted on the cut as its plane (the lower one's top). `outline`:
// what the cluster's outline says for two bodies against one, on the criterion's scale
// (width_step's; 0: nothing); its model, two upright solids, must then hold for the two
// parts' fits (a milk carton's gable, fitted lying on the body, is its top).
std::optional<TouchingCut> level_cut_at(
    const Frame& f, const ScanCluster& cluster, const std::vector<double>& height, double cut,
    double outline, const FitTerms& whole, double least,
    const std::function<void(ScanCluster&, std::vector<Vec3>&)>& refit,
    const ShapeRecognizerParams& shape, const TouchingSplitParams& params) {
  const Vec3 n = cluster.support.normal;
  ScanCluster a, b;
  a.support = cluster.support;
  b.support = Plane{n, cluster.support.d - cut};
  for (size_t k = 0; k < height.size(); ++k)
    (height[k] >= cut ? b : a).pixels.push_back(cluster.pixels[k]);
  if (static_cast<double>(std::min(a.pixels.size(), b.pixels.size())) < least) return std::nullopt;
  // The upper part is fitted first (refit_parts), the lower only when the upper is a
  // body: explained, and with the outline's model an upright solid.
  const auto upper_body = [&](const ScanCluster& part, const FitTerms& t) {
    return t.coverage >= params.min_part_coverage &&
           (outline <= 0 || upright_solid(part.shape.primitives.front().primitive, n));
  };
  std::vector<Vec3> na, nb;
  const std::optional<std::pair<FitTerms, FitTerms>> terms =
      refit_parts(f, a, b, na, nb, refit, shape, upper_body);
  if (!terms) return std::nullopt;
  const auto& [ta, tb] = *terms;
  if (!both_recognised(ta, tb, params.min_part_coverage)) return std::nullopt;
  const Criterion k = criterion(whole, ta, tb, shape);
  if (!(k.two - outline < k.one)) return std::nullopt;
  const ShapeFit &fa = a.shape.primitives.front(), &fb = b.shape.primitives.front();
  if (outline > 0 && !upright_solid(fa.primitive, n)) return std::nullopt;
  // Two bodies of different heights side by side step in outline as a stack does, but
  // the lower part is then two bodies, and stands on two feet; a stack's lower part is
  // one (the touching cuts' test: touching_split.h).
  if (outline > 0 && stands_on_two_feet(f, a, params)) return std::nullopt;
  // The upper body stands over the lower's footprint.
  const Vec3 apart = fb.primitive.center - fa.primitive.center;
  if (norm(apart - n * dot(n, apart)) > footprint_radius(fa)) return std::nullopt;
  b.support = cluster.support;  // the scanner's support; the stacking refits it on a's top
  return TouchingCut{std::move(a), std::move(b), std::move(na), std::move(nb)};
}

// Each pixel's height over the cluster's support.
std::vector<double> heights_of(const Frame& f, const ScanCluster& cluster) {
  std::vector<double> height(cluster.pixels.size());
  for (size_t k = 0; k < cluster.pixels.size(); ++k) {
    const PointXYZRGB& p = f.points[static_cast<size_t>(cluster.pixels[k])];
    height[k] = dot(cluster.support.normal, Vec3{p.x, p.y, p.z}) + cluster.support.d;
  }
  return height;
}

// Stacked bodies one primitive explains poorly (one standing on the other, too far for
// the segmenter's crease test): what the one primitive leaves out lies above or below
// what it explains. The cut is level, at the left-out pixels' lowest heights when they
// lie higher than the rest (the upper body left out) or at their highest when lower,
// with two thirds of the explained pixels on the other side; each part at least
// the segmenter's level_min_height_m tall; then level_cut_at.
std::optional<TouchingCut> level_misfit_cut(
    const Frame& f, const ScanCluster& cluster, const std::vector<char>& left_out,
    const FitTerms& whole, double least,
    const std::function<void(ScanCluster&, std::vector<Vec3>&)>& refit,
    const ShapeRecognizerParams& shape, const TouchingSplitParams& params) {
  const std::vector<double> height = heights_of(f, cluster);
  std::vector<double> out_h, kept_h;
  for (size_t k = 0; k < height.size(); ++k) (left_out[k] ? out_h : kept_h).push_back(height[k]);
  if (out_h.empty() || kept_h.empty()) return std::nullopt;
  const bool upper_left_out = quantile(out_h, 0.5) > quantile(kept_h, 0.5);
  const double cut = upper_left_out ? quantile(out_h, 0.05) : quantile(out_h, 0.95);
  double low = cut, high = cut;
  for (double h : height) low = std::min(low, h), high = std::max(high, h);
  if (cut - low < params.segment.level_min_height_m ||
      high - cut < params.segment.level_min_height_m)
    return std::nullopt;
  // What the one primitive explains lies on the other side, two thirds of it at least
  // (as misfit_on_one_side asks of a side-by-side cut): it is the other body's fit, not
  // one object's whose misfit runs up its height (the milk frame's carton, its flaps).
  const auto other_side = std::count_if(
      kept_h.begin(), kept_h.end(), [&](double h) { return upper_left_out ? h < cut : h >= cut; });
  if (3 * other_side < 2 * static_cast<std::ptrdiff_t>(kept_h.size())) return std::nullopt;
  return level_cut_at(f, cluster, height, cut, 0, whole, least, refit, shape, params);
}

// The silhouette's slices are this many pixel footprints tall, each seen in at least
// kStepSlicePoints pixels; each side of a step spans kStepMinSlices slices or more (a
// line through fewer is at the mercy of one slice: a rim, a handle's end).
constexpr double kStepSliceFootprints = 2;
constexpr int kStepSlicePoints = 3;
constexpr int kStepMinSlices = 5;
// ... and shows its outline in at least this share of the slices it spans.
constexpr double kStepSeenShare = 0.5;
// A step in width is at least a pixel on either side (the silhouette's quantisation), and
// wider than a lid or a label's ridge stands out of one body (a jar's lid: 2-3 mm a side).
constexpr double kStepMinFootprints = 2;
constexpr double kStepMinWidth_m = 0.01;
// An edge pixel is hidden where a pixel of something else within kOccluderReachPx beyond
// it along its image row, outwards, lies nearer than it by kOccluderSigmas of the depth
// noise (a centimetre at least): there the outline is the nearer object's, not the
// cluster's (the pixel next to it may mix the two depths).
constexpr int kOccluderReachPx = 6;
constexpr double kOccluderSigmas = 3;
constexpr double kOccluderLeast_m = 0.01;

// Whether something nearer hides the cluster beyond its edge pixel i, looking along the
// image row in direction `step` (+1 or -1); `own`: the cluster's pixels, sorted.
bool occluded_edge(const Frame& f, int i, int step, const std::vector<int>& own,
                   const DepthNoise& noise) {
  const PointXYZRGB& p = f.points[static_cast<size_t>(i)];
  const double nearer = p.z - std::max(kOccluderLeast_m, kOccluderSigmas * noise.sigma_z(p.z));
  const int x = i % f.width;
  for (int k = 1; k <= kOccluderReachPx; ++k) {
    const int xk = x + k * step;
    if (xk < 0 || xk >= f.width) return false;
    const int j = i + k * step;
    const PointXYZRGB& q = f.points[static_cast<size_t>(j)];
    if (has_depth(q) && q.z < nearer && !std::binary_search(own.begin(), own.end(), j)) return true;
  }
  return false;
}

// The top face and its rim lie within this many sigmas of the depth noise of the
// cluster's top (the height 99 % of its pixels lie under): a rim pixel mixes the face
// and the side, and its noise runs along its ray, which grazes the rim.
constexpr double kTopFaceSigmas = 3;

// Least-squares line w = a + b h over slices, from their sums; its residual sum of
// squares, and its value at h.
struct LineSums {
  double n = 0, h = 0, hh = 0, w = 0, hw = 0, ww = 0;
  void add(double x, double y) { n += 1, h += x, hh += x * x, w += y, hw += x * y, ww += y * y; }
  LineSums minus(const LineSums& o) const {
    return {n - o.n, h - o.h, hh - o.hh, w - o.w, hw - o.hw, ww - o.ww};
  }
  std::array<double, 2> line() const {
    const double det = n * hh - h * h;
    if (!(std::abs(det) > 1e-18)) return {n > 0 ? w / n : 0, 0};
    const double b = (n * hw - h * w) / det;
    return {(w - b * h) / n, b};
  }
  double rss() const {
    const auto [a, b] = line();
    return std::max(0.0, ww - 2 * a * w - 2 * b * hw + a * a * n + 2 * a * b * h + b * b * hh);
  }
};

// The outline of a cluster's height in slices: each slice's height and its width along
// `across` (level, across the line of sight), for the slices seen in kStepSlicePoints
// pixels or more below `top_face`, whose two edges no nearer object hides.
std::vector<std::array<double, 2>> outline_widths(const Frame& f, const ScanCluster& cluster,
                                                  const std::vector<double>& height, Vec3 across,
                                                  double low, double slice, double top_face,
                                                  const DepthNoise& noise) {
  const auto slices = static_cast<size_t>((top_face - low) / slice) + 1;
  std::vector<double> lo(slices, 1e9), hi(slices, -1e9);
  std::vector<int> count(slices, 0), lo_px(slices, -1), hi_px(slices, -1);
  for (size_t k = 0; k < height.size(); ++k) {
    if (height[k] > top_face) continue;
    const int i = cluster.pixels[k];
    const PointXYZRGB& p = f.points[static_cast<size_t>(i)];
    const double u = dot(across, Vec3{p.x, p.y, p.z});
    const auto j = std::min(slices - 1, static_cast<size_t>((height[k] - low) / slice));
    if (u < lo[j]) lo[j] = u, lo_px[j] = i;
    if (u > hi[j]) hi[j] = u, hi_px[j] = i;
    ++count[j];
  }
  std::vector<int> own = cluster.pixels;
  std::sort(own.begin(), own.end());
  const int out = across.x >= 0 ? 1 : -1;  // the image column's step as u grows (+x right)
  std::vector<std::array<double, 2>> widths;
  for (size_t j = 0; j < slices; ++j)
    if (count[j] >= kStepSlicePoints && !occluded_edge(f, lo_px[j], -out, own, noise) &&
        !occluded_edge(f, hi_px[j], out, own, noise))
      widths.push_back({low + (static_cast<double>(j) + 0.5) * slice, hi[j] - lo[j]});
  return widths;
}

// The best break of an outline into two lines: the slices below it, its height, the
// step between the two lines there and their residuals together (none found: no slices
// below). Each side spans kStepMinSlices slices, min_height of the cluster's height from
// `low` or up to `high`, and shows its outline in kStepSeenShare of the slices it spans.
struct OutlineBreak {
  size_t below = 0;
  double height = 0, step = 0, rss = 0;
};
OutlineBreak best_break(const std::vector<std::array<double, 2>>& widths, double low, double high,
                        double top_face, double slice, double min_height) {
  const size_t m = widths.size();
  LineSums all;
  std::vector<LineSums> below(m + 1);  // sums over the first k slices
  for (size_t k = 0; k < m; ++k) {
    all.add(widths[k][0], widths[k][1]);
    below[k + 1] = all;
  }
  OutlineBreak best{0, 0, 0, all.rss()};
  for (size_t k = kStepMinSlices; k + kStepMinSlices <= m; ++k) {
    const double cut = 0.5 * (widths[k - 1][0] + widths[k][0]);
    if (cut - low < min_height || high - cut < min_height) continue;
    if (static_cast<double>(k) < kStepSeenShare * (cut - low) / slice ||
        static_cast<double>(m - k) < kStepSeenShare * (top_face - cut) / slice)
      continue;
    const LineSums upper = all.minus(below[k]);
    const double rss = below[k].rss() + upper.rss();
    if (rss >= best.rss) continue;
    const auto [al, bl] = below[k].line();
    const auto [au, bu] = upper.line();
    best = {k, cut, (au + bu * cut) - (al + bl * cut), rss};
  }
  return best;
}

// Where an upright cluster's silhouette steps in width: a body standing on one wider or
// narrower than itself, too far for the crease test and explained well by one primitive
// (a tin on a wider tin is one cone through both at 2 m). The width across the line of
// sight, on the support, of each slice of the cluster's height is a straight line in
// height for one solid of revolution or box (constant for a cylinder, sloped for a
// cone); two lines meeting in a step of kStepMinFootprints pixels and kStepMinWidth_m,
// which the two parts' median widths show too, chosen over one by the Bayesian
// information criterion over the slices (two more lines' parameters and the break),
// mark two bodies. Returns the step's height over the support and that criterion's
// margin: the outline's evidence for two bodies, which the depth residuals barely hold
// far away (the step is lateral, where a pixel is several times finer than the depth
// noise at 2 m).
struct WidthStep {
  double height = 0, evidence = 0;
};
std::optional<WidthStep> width_step(const Frame& f, const ScanCluster& cluster,
                                    const std::vector<double>& height, const FitTerms& whole,
                                    const TouchingSplitParams& params) {
  // One primitive explains it: a body with a neck (a bottle) is what the recognizer
  // already made of a narrower part above a wider one.
  if (cluster.shape.primitives.size() != 1 || height.empty()) return std::nullopt;
  const Vec3 n = cluster.support.normal;
  if (!upright_solid(cluster.shape.primitives.front().primitive, n)) return std::nullopt;
  Vec3 mean{0, 0, 0};
  for (int i : cluster.pixels) {
    const PointXYZRGB& p = f.points[static_cast<size_t>(i)];
    mean = mean + Vec3{p.x, p.y, p.z};
  }
  const double pixel = whole.depth / whole.focal_px, slice = kStepSliceFootprints * pixel;
  const auto [low, high] = std::minmax_element(height.begin(), height.end());
  // A top face seen from above spans the whole cross-section, the sides below only what
  // the camera sees of it (a box turned to the camera: its far corners), and the rim's
  // pixels narrow the outline's last slices: the face's and the rim's are left out.
  const double top_face =
      quantile(height, 0.99) - slice - kTopFaceSigmas * whole.noise.sigma_z(whole.depth);
  if (top_face - *low < 2 * kStepMinSlices * slice || *high - *low > 4096 * slice)
    return std::nullopt;
  const std::vector<std::array<double, 2>> widths = outline_widths(
      f, cluster, height, normalized(cross(n, mean)), *low, slice, top_face, whole.noise);
  const size_t m = widths.size();
  if (m < 2 * kStepMinSlices) return std::nullopt;
  const OutlineBreak cut =
      best_break(widths, *low, *high, top_face, slice, params.segment.level_min_height_m);
  const double least_step = std::max(kStepMinFootprints * pixel, kStepMinWidth_m);
  if (cut.below == 0 || std::abs(cut.step) < least_step) return std::nullopt;
  // The step holds over most of each part: their median widths differ by as much, the
  // same way (a cylinder's rim narrowing its last slices is no narrower body on it).
  std::vector<double> lower_w, upper_w;
  for (size_t k = 0; k < m; ++k) (k < cut.below ? lower_w : upper_w).push_back(widths[k][1]);
  const double medians = quantile(upper_w, 0.5) - quantile(lower_w, 0.5);
  if (medians * cut.step <= 0 || std::abs(medians) < least_step) return std::nullopt;
  // Two lines and the break (three more parameters) against one line, over m slices.
  // Neither model's residuals fall below the quantisation of the slices' two edges to
  // the pixel grid (each uniform over a pixel: a sixth of a pixel squared together per
  // slice); widths a whole number of pixels apart would otherwise fit two lines exactly.
  LineSums all;
  for (const auto& [h, w] : widths) all.add(h, w);
  const double dm = static_cast<double>(m), least_rss = dm * pixel * pixel / 6;
  const double evidence =
      dm * std::log(std::max(all.rss(), least_rss) / std::max(cut.rss, least_rss)) -
      3 * std::log(dm);
  if (!(evidence > 0)) return std::nullopt;
  return WidthStep{cut.height, evidence};
}

// The smaller part's fewest pixels: min_part_share of the cluster's and those of a body
// min_part_size_m wide at its depth.
double least_part_pixels(const ScanCluster& cluster, const FitTerms& whole,
                         const TouchingSplitParams& params) {
  const int min_points = min_part_pixels(params.min_part_size_m, whole.depth, whole.focal_px);
  return std::max(params.min_part_share * static_cast<double>(cluster.pixels.size()),
                  static_cast<double>(min_points));
}

// The cuts along what one primitive leaves out of a cluster it explains poorly: the
// means' cut, else along the misfit, beside the primitive or level (touching_cut).
std::optional<TouchingCut> misfit_cuts(
    const Frame& f, const ScanCluster& cluster, const FitTerms& whole,
    const std::function<void(ScanCluster&, std::vector<Vec3>&)>& refit,
    const ShapeRecognizerParams& shape, const TouchingSplitParams& params) {
  const int min_points = min_part_pixels(params.min_part_size_m, whole.depth, whole.focal_px);
  const double least = least_part_pixels(cluster, whole, params);
  const MeansCut means = two_means(f, cluster, params.min_part_share, min_points);
  // Explained that well, it is tried only on two feet: the refits cost as much whether
  // the cut is kept or not.
  if (whole.coverage >= params.two_feet_coverage && !whole.level_cylinder &&
      !two_feet(f, cluster, means, whole.depth, params))
    return std::nullopt;
  const auto narrows = [&] {
    return params.waist_share > 0 && footprint_waist(means, params.waist_share);
  };
  if (!means.side.empty() && (misfit_on_one_side(f, cluster, means.side, shape) || narrows()))
    if (std::optional<TouchingCut> cut =
            refit_cut(f, cluster, means.side, whole, least, refit, shape, params))
      return cut;
  // The means' cut halves the larger body when the two differ in size (fresh rooms 9571:
  // a flat bowl against a box of twice its pixels, each half unexplained): the cut along
  // what the one primitive leaves out, when that is a body's worth of pixels beside it.
  if (!params.misfit_cut) return std::nullopt;
  const std::vector<char> left_out = misfit_side(f, cluster, shape);
  const auto out = static_cast<double>(std::count(left_out.begin(), left_out.end(), 1));
  // The one primitive is the larger body's fit: it explains at least half of the pixels
  // (the milk frame's detergent bottle: 41 % by this count, its handle and veil no body).
  const double kept = static_cast<double>(left_out.size()) - out;
  if (out < least || kept < out) return std::nullopt;
  if (beside_primitive(f, cluster, left_out))
    return refit_cut(f, cluster, left_out, whole, least, refit, shape, params);
  if (params.level_cut)
    return level_misfit_cut(f, cluster, left_out, whole, least, refit, shape, params);
  return std::nullopt;
}

}  // namespace

std::optional<TouchingCut> touching_cut(
    const Frame& f, const ScanCluster& cluster,
    const std::function<void(ScanCluster&, std::vector<Vec3>&)>& refit,
    const std::function<bool(const ScanCluster&)>& seen_whole, const ShapeRecognizerParams& shape,
    const TouchingSplitParams& params) {
  const FitTerms whole = terms_of(f, cluster, shape.depth_noise);
  // A cylinder lying on its side is what two round objects side by side look like
  // together (two balls, a ball against a ring): however much of them it explains, the
  // cut is tried, and the criterion between one body and two decides.
  const bool explained_poorly = whole.coverage < params.max_whole_coverage || whole.level_cylinder;
  if (explained_poorly) {
    if (!seen_whole(cluster)) return std::nullopt;
    if (std::optional<TouchingCut> cut = misfit_cuts(f, cluster, whole, refit, shape, params))
      return cut;
  }
  // A far stack one primitive explains well shows where its silhouette steps in width.
  // One it explains poorly has had the level cut along its misfit; where the crease test
  // is blind (beyond about 2 m), the outline is tried on it too.
  if (!params.width_step_cut ||
      (explained_poorly && !crease_test_blind(whole.depth, whole.focal_px, params.segment)))
    return std::nullopt;
  const std::vector<double> height = heights_of(f, cluster);
  const std::optional<WidthStep> step = width_step(f, cluster, height, whole, params);
  if (!step || (!explained_poorly && !seen_whole(cluster))) return std::nullopt;
  return level_cut_at(f, cluster, height, step->height, step->evidence, whole,
                      least_part_pixels(cluster, whole, params), refit, shape, params);
}

bool stands_on_two_feet(const Frame& f, const ScanCluster& cluster,
                        const TouchingSplitParams& params) {
  const FitTerms whole = terms_of(f, cluster, params.depth_noise);
  const int min_points = min_part_pixels(params.min_part_size_m, whole.depth, whole.focal_px);
  return two_feet(f, cluster, two_means(f, cluster, params.min_part_share, min_points), whole.depth,
                  params);
}

}  // namespace annex
