// Point residuals of the shape recognizer's least-squares refinements, each with its
// analytic gradient in the parameters (Levenberg-Marquardt's Jacobian row). The values
// are the recognizer's own residuals term for term; `g`, when not null, receives the
// gradient. Coordinates are the support frame's: a, b across the plane, h above it.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cmath>

namespace annex::shape_residuals {

template <int N>
using Gradient = Eigen::Matrix<double, N, 1>;

// d|x|/dx, taken as +1 at 0 (the side a forward difference takes).
inline double sign_of(double x) { return x < 0 ? -1.0 : 1.0; }

// x / d, 0 where d is 0 (a point on the axis: the distance's gradient is undefined).
inline double over(double x, double d) { return d > 0 ? x / d : 0.0; }

// Circle p = (centre a, centre b, radius): distance of (qa, qb) from it.
inline double circle(const std::array<double, 3>& p, double qa, double qb, Gradient<3>* g) {
  const double da = qa - p[0], db = qb - p[1];
  const double d = std::sqrt(da * da + db * db);
  if (g) *g << -over(da, d), -over(db, d), -1.0;
  return d - p[2];
}

// Upright cone p = (axis a, axis b, radius at t = 0, radius at t = 1), t the point's
// height along the fitted span `span`: the radial miss over the side's slant factor
// sqrt(1 + slope^2), the distance across the side.
// The cone's terms that do not depend on the point (its slope, the slant factor and its
// inverse), for a pass over many points with the same parameters.
struct ConeTerms {
  double slope = 0, root = 1, u = 1;
};
inline ConeTerms cone_terms(const std::array<double, 4>& p, double span) {
  ConeTerms k;
  k.slope = (p[3] - p[2]) / span;
  k.root = std::sqrt(1 + k.slope * k.slope);
  k.u = 1 / k.root;
  return k;
}
inline double cone(const std::array<double, 4>& p, double qa, double qb, double t, double span,
                   const ConeTerms& k, Gradient<4>* g) {
  const double da = qa - p[0], db = qb - p[1];
  const double d = std::sqrt(da * da + db * db);
  const double slope = k.slope;
  const double e = d - (p[2] + (p[3] - p[2]) * t);
  const double r = e / k.root;
  if (g) {
    const double u = k.u;
    // d(1/root)/d(slope) = -slope u^3; d(slope)/d(r0) = -1 / span, d(slope)/d(r1) = 1 / span.
    const double tilt = e * slope * u * u * u / span;
    *g << -over(da, d) * u, -over(db, d) * u, -(1 - t) * u + tilt, -t * u - tilt;
  }
  return r;
}
inline double cone(const std::array<double, 4>& p, double qa, double qb, double t, double span,
                   Gradient<4>* g) {
  return cone(p, qa, qb, t, span, cone_terms(p, span), g);
}

// Sphere p = (centre a, b, h, radius).
inline double sphere(const std::array<double, 4>& p, double qa, double qb, double qh, Gradient<4>* g) {
  const double da = qa - p[0], db = qb - p[1], dh = qh - p[2];
  const double d = std::sqrt(da * da + db * db + dh * dh);
  if (g) *g << -over(da, d), -over(db, d), -over(dh, d), -1.0;
  return d - p[3];
}

// Sphere resting on the plane p = (centre a, centre b, radius): centre one |radius| up.
inline double resting_sphere(const std::array<double, 3>& p, double qa, double qb, double qh,
                             Gradient<3>* g) {
  const double r = std::abs(p[2]);
  const double da = qa - p[0], db = qb - p[1], dh = qh - r;
  const double d = std::sqrt(da * da + db * db + dh * dh);
  if (g) *g << -over(da, d), -over(db, d), sign_of(p[2]) * (-over(dh, d) - 1);
  return d - r;
}

// Torus lying flat p = (centre a, centre b, major radius, minor radius): the tube's
// centre circle at height p[3].
inline double torus(const std::array<double, 4>& p, double qa, double qb, double qh, Gradient<4>* g) {
  const double da = qa - p[0], db = qb - p[1];
  const double rho = std::sqrt(da * da + db * db);
  const double dr = rho - p[2], dh = qh - p[3];
  const double d = std::sqrt(dr * dr + dh * dh);
  if (g) {
    const double radial = over(dr, d);
    *g << -radial * over(da, rho), -radial * over(db, rho), -radial, -over(dh, d) - sign_of(p[3]);
  }
  return d - std::abs(p[3]);
}

// Cross-section of a cylinder lying on the plane p = (offset across its axis, radius):
// a circle touching the plane, (w, h) the point's offset across the axis and height.
inline double lying_circle(const std::array<double, 2>& p, double w, double h, Gradient<2>* g) {
  const double r = std::abs(p[1]);
  const double dw = w - p[0], dh = h - r;
  const double d = std::sqrt(dw * dw + dh * dh);
  if (g) *g << -over(dw, d), sign_of(p[1]) * (-over(dh, d) - 1);
  return d - r;
}

}  // namespace annex::shape_residuals

namespace annex::shape_residuals {

// cos 4 phi and sin 4 phi of the direction (x, y), phi = atan2(y, x), without trig: the
// unit direction as a complex number, squared twice (normal azimuths modulo 90 degrees,
// averaged as 4x angles). (0, 0) gives (1, 0), as phi = atan2(0, 0) = 0 does.
inline std::array<double, 2> fourfold(double x, double y) {
  const double r2 = x * x + y * y;
  if (!(r2 > 0)) return {1.0, 0.0};
  const double c2 = (x * x - y * y) / r2, s2 = 2 * x * y / r2;
  return {c2 * c2 - s2 * s2, 2 * s2 * c2};
}

// Rectangle p = (centre a, centre b, azimuth, half side x, half side y) seen from above
// (a box's outline): the signed distance of (qa, qb) from its boundary, negative inside.
// Piecewise smooth (kinks in |.| and max); the gradient is each piece's, the side a
// forward difference takes at a kink (sign_of; the larger offset inside).
inline double rectangle(const std::array<double, 5>& p, double qa, double qb, Gradient<5>* g) {
  const double cs = std::cos(p[2]), sn = std::sin(p[2]);
  const double da = qa - p[0], db = qb - p[1];
  const double u = cs * da + sn * db, v = -sn * da + cs * db;
  const double ox = std::abs(u) - std::abs(p[3]), oy = std::abs(v) - std::abs(p[4]);
  // d ox and d oy in the parameters: u, v turn with the azimuth (du = v, dv = -u).
  const double su = sign_of(u), sv = sign_of(v);
  const Gradient<5> dox{-su * cs, -su * sn, su * v, -sign_of(p[3]), 0.0};
  const Gradient<5> doy{sv * sn, -sv * cs, -sv * u, 0.0, -sign_of(p[4])};
  if (ox <= 0 && oy <= 0) {
    if (g) *g = ox < oy ? doy : dox;
    return std::max(ox, oy);
  }
  const double mx = std::max(ox, 0.0), my = std::max(oy, 0.0);
  const double d = std::sqrt(mx * mx + my * my);
  if (g) *g = (mx * dox + my * doy) / d;
  return d;
}

}  // namespace annex::shape_residuals
