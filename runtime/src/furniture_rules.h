#pragma once
// Rules that tell furniture and room surfaces from props, on a cluster of the scan's
// strided grid before its shape is fitted (docs/perception.md, "Every support
// surface"). Private to the scanner: scan_frame calls them after the leg, body and
// under-support rules. Each takes the cluster's grid pixels (full-resolution indices,
// every `step`-th pixel), its support's plane (n . p + d = height above it) and the
// cluster tolerance at a depth (it widens with the Kinect's noise).

#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/physical_scene.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/object_shape_recognizer.h"
#include "annex/runtime/scanner.h"

namespace annex {

using ToleranceAt = std::function<double(double z)>;

// (image column, the cluster's topmost (`top`) or lowest grid pixel in it), by column.
std::vector<std::pair<int, int>> end_per_column(const Frame& f, const std::vector<int>& grid,
                                                bool top);

// Whether the cluster's top is the height band's top across most of its width: in at
// least params.cut_top_share of its grid columns whose topmost pixel lies at the band's
// top (within the tolerance; three at least), that pixel's neighbour one or two grid rows
// up lies above max_height_m and continues its surface with no depth step (no farther
// from it than the rows below are spaced, plus the noise). Columns whose topmost pixel
// lies lower cross the silhouette's side, not its top (a post 3 m away, slanted in the
// image by a tilted view: fresh rooms 8029), and count for neither. A prop's top ends
// below the band (the wall behind it is a step away); a wardrobe's or a chair back's
// front runs on, row after row, wherever the band cuts it. Counted per column, so a wide
// front whose rows are spaced 2 to 5 cm apart by a steep view and the noise is not
// missed because its top edge is short against its area (continues_above asks for joins
// in a fiftieth of the cluster's pixels, and joins only within the tolerance).
bool top_cut_by_band(const Frame& f, const std::vector<int>& grid, int step, Vec3 n, double d,
                     const ScanParams& params, const ToleranceAt& tolerance);

// Whether the cluster is the upper part of a body the height band of a lower support
// cut: in more than half of its grid columns (three at least) the first valid pixel one
// to three grid rows below its lowest pixel continues its surface (no farther from it in
// depth than the tolerance) and is a pixel `cut_below` names: one of a cluster that
// top_cut_by_band takes (a chair's back seen from behind, rising past the floor's band
// beside its seat, whose upper part the seat's reach takes). What stands on its support
// has that support's surface below its foot, or the object it stands on.
bool foot_on_cut_body(const Frame& f, const std::vector<int>& grid, int step,
                      const std::function<bool(int)>& cut_below, const ToleranceAt& tolerance);

// Whether something nearer hides the cluster's top: in more than half of its grid
// columns the first valid pixel one to three grid rows above its topmost pixel is nearer
// to the camera than that pixel by more than the tolerance (a shelf's board, a seat, a
// nearer object). No one sees where such a cluster ends: the wall under a shelf's
// board, a bin under a seat. A prop seen whole has its top against what lies behind
// it, or against nothing.
bool top_occluded(const Frame& f, const std::vector<int>& grid, int step,
                  const ToleranceAt& tolerance);

// Whether the view passes over the cluster's top to what lies behind it: in more than
// half of its grid columns (three at least) the first valid pixel one to three grid rows
// above its topmost pixel is farther than that pixel by more than the tolerance. Its top
// is seen, so it ends there: nothing of it rises on to meet what is above.
bool top_seen_ending(const Frame& f, const std::vector<int>& grid, int step,
                     const ToleranceAt& tolerance);

// Whether the cluster's lowest point (`bottom_h` above its support) lies more than
// params.hidden_foot_min_height_m above the support and something nearer hides its foot:
// in more than half of its grid columns the first valid pixel one to three grid rows
// below its lowest pixel is nearer than that pixel by more than the tolerance. No one
// sees what holds it up there, at furniture height: a chair's seat behind its own back
// seen from behind, a seat or board behind the table's top. Flagged partial, as a
// cluster whose top is hidden is. With params.partial_when_seen_under, columns where the
// view passes under it (foot_view: farther) count as well: hidden or seen under, nothing
// at the foot's depth holds it up (a back chair's seat seen from just above it, the floor
// beyond it showing under its edge beside the back that hides the rest).
bool foot_hidden_high(const Frame& f, const std::vector<int>& grid, int step, double bottom_h,
                      const ScanParams& params, const ToleranceAt& tolerance);

// What lies one to three grid rows below the cluster's lowest pixel in each of its grid
// columns: the first valid pixel nearer to the camera than that pixel by more than the
// tolerance (something in front hides the foot), or farther by as much (the view passes
// under the cluster to what lies behind it).
struct FootView {
  int columns = 0, nearer = 0, farther = 0;
};
FootView foot_view(const Frame& f, const std::vector<int>& grid, int step, const ToleranceAt& tolerance);

// Whether the view passes on beyond the cluster's end, to something farther, in more
// than half of its columns (at least three).
bool seen_past(const FootView& v);

// Whether the cluster hangs over its support with nothing of its own under it: the view
// passes under it (the first valid pixel below its lowest one lies farther, foot_view, in
// more than half of its grid columns) and its lowest point `low`, `low_h` above the
// support (n . p + d), lies higher than a body hidden beneath it could reach down from
// it. What stands on a support shows its foot there, or hides it in its own shadow along
// the view: a bowl wide end up seen from above hides its foot under its rim. That shadow
// reaches below the lowest point at most the cluster's depth times the view's slope
// there (its tangent: the camera's height over the support less the point's, over the
// point's run along the plane), the depth taken as its `width` across the view (a prop
// is about as deep as it is wide). A shelf's board 25 cm up on side panels outside the
// cluster, or a lamp's head on its arm, hangs higher than that: no one sees what holds
// it up (params.partial_when_seen_under).
bool hangs_seen_under(const Frame& f, const std::vector<int>& grid, int step, Vec3 n, double d, Vec3 low,
                      double low_h, double width, const ToleranceAt& tolerance);

// Whether the view just under the cluster meets something raised before its support: in
// more than half of the middle third of its grid columns the first valid pixel one to
// three grid rows below its lowest pixel lies behind the cluster's farthest point (more
// than the tolerance there) and higher above the support than `bands` times the
// support's band at its depth (`band`). A body standing on its support hides its foot
// under its middle, so the ray grazing its lowest point there reaches that support in
// front of the foot, before anything behind the body: a ball's bulge, a bowl's rim. A
// shelf's board front 20 cm up shows the wall 30 cm behind it there: nothing of its own
// reaches down to hold it (params.seen_under_raised_bands). Beside the foot (the outer
// thirds) a view under a cup's rim may pass on to the wall; just behind the body's
// lowest point lies what it is stacked on, or its own lower piece.
bool view_under_meets_raised(const Frame& f, const std::vector<int>& grid, int step,
                             const Plane& support, double bands, const ToleranceAt& tolerance,
                             const ToleranceAt& band);

// Whether a higher support's top, nearer, hides the cluster's foot: in more than half of
// its grid columns the first valid pixel one to three grid rows below its lowest pixel is
// nearer than that pixel by more than the tolerance and lies on the surface region of a
// support for which `higher` holds (`surface_of` as for foot_unseen). No one sees where
// what stands behind a table's or a cabinet's top ends below it: a shelf's board or side
// behind the table (rooms 5105, fresh rooms 9810), a box on the floor behind a cabinet
// (fresh rooms 9580). A prop behind a nearer prop has that prop, no support's surface, in
// front of its foot (foot_hidden_high's rule).
bool foot_behind_higher_support(const Frame& f, const std::vector<int>& grid, int step,
                                const std::vector<int>& surface_of,
                                const std::function<bool(int)>& higher,
                                const ToleranceAt& tolerance);

// Whether the cluster's foot is not seen on its support: in more than half of the grid
// columns that show anything below its lowest pixel, the first valid pixel one to three
// grid rows below is no point of its support's surface region (`surface_of`: the
// support index of each pixel of a support's region, -1 none). What stands on a support
// has that surface at its foot; a chair's back behind the table runs on down past the
// table's far edge (its points there lie on the table's plane but face sideways, so
// they are no part of the table's region), or a nearer thing hides its foot.
bool foot_unseen(const Frame& f, const std::vector<int>& grid, int step,
                 const std::vector<int>& surface_of, int support);

// The plane fitted to the support's own pixels around the cluster (`surface_of`: the
// support index of each strided pixel of a support's region): those in the cluster's
// image box grown by half its larger side on every side. The support's plane is one fit
// over every pixel of the frame in its band, which a lower desk, the wall's foot or
// objects' feet tilt by a centimetre or more at the far end; around one cluster its own
// surface is flat to the noise. Needs 30 support pixels, and a normal within
// params.max_support_tilt_deg of the support's (`support_n`); nullopt otherwise.
std::optional<Plane> own_support_around(const Frame& f, const std::vector<int>& grid, int step,
                                        const std::vector<int>& surface_of, int support,
                                        Vec3 support_n, const ScanParams& params);

// Whether the cluster is a piece of its own support's surface: nine in ten of its points
// lie within the support's band at their depth (`band`, params.min_height_m at least)
// above the support's plane around it (own_support_around), the band every object's
// pixels lie above. A strip of a table's near edge stands 1 to 6 cm above the support's
// one plane (unseen 3038, fresh rooms 8037, 8077, 8097, 8104), and a far floor's slab
// 4 to 8 cm above its tilted plane (rooms 5059, 3.4 m away), yet each lies on its
// surface around it. A prop stands above that surface by its height. False with
// params.support_slab_check off.
bool lies_on_own_support(const Frame& f, const std::vector<int>& grid, const Plane& around,
                         const ScanParams& params, const ToleranceAt& band);

// The face's normal when the cluster is one upright flat face: its points' spread along their
// least-spread direction is at most params.panel_noise_factor times the Kinect's axial
// noise at their mean depth, and that direction lies within 30 degrees of horizontal
// (an upright face). A solid seen from above its top (every camera here is: a support
// is seen from above) shows its top or its curve, which spreads it well past the noise
// (a box 10 cm deep 1 m away: 8 times). One face alone is no evidence against a prop
// (a laptop's lid, a box seen face-on from afar); with its foot unseen (foot_unseen) it
// is a chair's back or a cabinet's side rising behind the table: flagged partial.
std::optional<Vec3> upright_panel(const Frame& f, const std::vector<int>& grid, Vec3 up,
                                  const ScanParams& params);

// Whether the cluster stands behind its support's far edge, lower down: in more than half
// of the grid columns that show its foot, its face runs on below its lowest pixel (no
// farther along the plane from that pixel than three sigma_z: the depth noise) to below
// the support's plane around it (own_support_around) by more than
// params.below_support_sigmas times the height noise there (sigma_z times the ray's
// slope against the plane) and at least 3 mm, and ends at the support's own surface
// (`surface_of`) nearer to the camera, or with params.below_support_ends_at_objects at
// what stands on it there (higher than params.min_height_m). A chair's back behind the
// table, or what stands on the floor behind it, runs on below the table's height until
// the table's edge hides it:
// no one sees its foot (the scanner flags it partial). What stands on the support ends at
// its surface; a box stacked flush on another runs on down the lower one's front to the
// floor, no surface of its support. False with params.below_support_sigmas 0.
bool runs_below_support(const Frame& f, const std::vector<int>& grid, int step, const Plane& around,
                        const std::vector<int>& surface_of, int support, const ScanParams& params);

// Whether the cluster's foot runs off the image's bottom edge (`bottom`: the last row
// that holds depth), unseen: in at least three of its columns its lowest pixel is within
// border_px of that row plus the rows its support's band spans at its depth (an object's
// lowest min_height_m lies in the band and is no cluster pixel, 13 rows half a metre
// away), or no pixel below it down to that row holds depth (a dark or too-near foot).
// Such an object is cut by the border as surely as one whose pixels reach it: no one sees
// where it ends (params.foot_at_border; a border sliver of the near table's objects).
bool foot_cut_by_bottom(const Frame& f, const std::vector<int>& pixels, int bottom,
                        const ScanParams& params, const ToleranceAt& band);

// The rectangle of rows and columns that holds depth (a Kinect leaves a few invalid ones
// at its edges), in full-resolution pixels.
struct DepthRect {
  int left = 0, top = 0, right = -1, bottom = -1;
};

// Whether the salient fit's foot, where it meets its support, lies within border_px of
// `rect`'s edge or beyond it, on any side: the outline samples (a cylinder's or cone's end
// circles, a box's corners, a torus's lowest circle, a sphere's foot) no higher than the
// support's band at their depth above the lowest one, projected. Those lowest few
// millimetres are the band's, no cluster pixel, so a flat cone whose foot ring runs off
// the side edge has no pixel near it (fresh rooms 10077); its fit says where the foot is.
bool fitted_foot_off_image(const Frame& f, const ShapeFit& fit, const Plane& support,
                           const DepthRect& rect, const ScanParams& params,
                           const ToleranceAt& band);

}  // namespace annex
