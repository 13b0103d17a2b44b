#pragma once
// The scanning pipeline of the paper (METHOD.md §2) on one depth frame: dominant
// near-horizontal plane, its convex hull, the prism of points above it, object
// clusters, Moving Least Squares smoothing, then ObjectShapeRecognizer per cluster.
// The fast path works on the organized 640x480 grid; scan_frame_pcl_reference
// (annex/reference/scanner_pcl_reference.h, bench and tests only) runs the paper's
// straightforward PCL pipeline for comparison (docs/perception.md).

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "annex/common/geometry.h"
#include "annex/common/physical_scene.h"
#include "annex/common/result.h"
#include "annex/runtime/depth_noise.h"
#include "annex/runtime/frame.h"
#include "annex/runtime/object_segmenter.h"
#include "annex/runtime/object_shape_recognizer.h"
#include "annex/runtime/plane_candidates.h"

namespace annex {

// Which supports' objects a scan reports (docs/perception.md).
enum class SupportSelection { all, nearest, highest, largest, id };

// Every field is a key of the scan config file (samples/config/scan.conf).
struct ScanParams {
  // Up direction in the camera frame (x right, y down, z forward); a Kinect looking
  // down at a table by `camera_tilt_deg` sees up as -y rotated about x.
  // The defaults accept supports seen from level (office1) to 75 degrees down.
  Vec3 up{0, -1, 0};
  double camera_tilt_deg = 30;
  // The camera's depth noise, which every tolerance below given in sigmas or "noise"
  // scales with (depth_noise.h): the Kinect's by default; config key `depth_noise`
  // kinect, stereo or tof, or `depth_noise_base_m`, `depth_noise_quadratic` and
  // `depth_noise_centre_m` for a fitted model. The scan hands it to the recognizer and
  // the segmenter (ShapeRecognizerParams, SegmenterParams::depth_noise).
  DepthNoise depth_noise;
  // Planes whose normal is further than this from up are not supports.
  double max_plane_angle_deg = 45;
  // The first plane's inliers, fitted by least squares, face within max_plane_angle_deg
  // of up too: else they are a band cut obliquely across a wall (a triple on the wall
  // tilted into the cone) and leave the search (a level camera seeing a wall behind a
  // table at a grazing angle). false: the RANSAC triple's plane alone (before session 10).
  bool first_plane_fits_up = true;
  // ... and so does the mean of the surface normals at them (each pixel's normal through
  // its neighbours): a strip of a wall no taller than the depth noise, cut by a band at a
  // slant, fits the band's own tilt, but its pixels' normals are the wall's (a level
  // camera facing a wall 2.5 m away). Asked with first_plane_fits_up only.
  bool first_plane_normals_up = true;
  // A pixel's surface normal (the up-facing test that gathers later supports' heights,
  // and the normals above) is taken through neighbours on its own surface: no further
  // from it than a surface seen at this incidence spans over the pixels between them,
  // plus three sigma of two returns' noise; where the neighbours a full reach away are
  // not, nearer ones are taken. A table's front face and the floor a metre behind it
  // span a normal that faces up: seen from 25 cm above, such pixels outnumbered the
  // table's top in the band below it (fresh rooms 9559). The Kinect returns almost
  // nothing from surfaces seen more obliquely than this. 90: any neighbour with depth
  // (before session 30).
  double surface_max_incidence_deg = 85;
  // The first plane is fitted again on the sensor's noise model: least squares weighted
  // by each point's axial noise, on the points within the noise-scaled band (below),
  // trimmed, round after round until it settles. RANSAC's fixed band is under one
  // sigma_z on a floor 3 m away, and least squares on the strip it cuts returns the
  // triple's own tilt. false: RANSAC's plane refined in the fixed band (session 28).
  bool first_plane_noise_fit = true;
  // ... which replaces RANSAC's plane when it turns it by at least this. Less is within
  // what the sensor's own depth distortion makes of a flat floor, where the noise
  // model's weights (the near part rules) and equal ones fit planes that far apart: the
  // real milk_cartoon floor, its far part bent 0.9 cm up, 0.17 degrees; nyu_basement's,
  // bent 2.6 cm over 2 to 4.5 m, 0.8. More is RANSAC's band stuck on its triple's tilt
  // (plain 6102: 9 degrees; held-out 5035: 2, its floor 8 cm off at the table).
  double noise_fit_min_turn_deg = 1.0;
  // Plane inlier band: this width, or plane_noise_factor times the camera's axial
  // noise at the point's depth where that is wider (far floor). Points within the
  // band are never object points.
  double plane_distance_m = 0.012;
  double plane_noise_factor = 2.5;
  int plane_iterations = 300;       // RANSAC samples
  int min_plane_points = 2000;      // full-resolution points
  // Supports are extracted one after another (each plane's inliers leave the search):
  // the first by RANSAC, the others at the heights where up-facing points concentrate,
  // until no such height holds a quarter of min_plane_points; at most this many planes are
  // kept (a bound on the cost, not a search budget: walls and rejected heights do not
  // count). Every near-horizontal one holding min_plane_points counts.
  int max_planes = 10;
  // Supports after the first are within this angle of its normal (a room's floor,
  // tables and shelves share one up) and span at least this much (a carton's top is
  // not a support; a box top of 20 x 20 cm is).
  double max_support_tilt_deg = 8;
  // Each raised support's plane (not the floor's) is fitted again on its own pixels
  // (weighted by the depth noise model, outliers trimmed) when the plane found for its
  // height band lies this many standard errors of that fit away, tilt and height
  // together: one plane through a table and a cabinet 4 cm lower beside it tilts 2
  // degrees to pass both. 0: the plane found for all its regions (before session 18).
  double support_fit_sigmas = 5;
  // ... and when the own fit's tilt is known to within this (its standard error): a
  // shelf's narrow board gives a tilt the noise decides.
  double support_fit_max_se_deg = 0.05;
  // ... or, its tilt unsure, its height alone (the found plane moved to its pixels'
  // weighted mean) when that lies support_fit_sigmas of its standard error and more than
  // plane_distance_m off the found plane, and nearer its pixels by their median
  // distance: one band's plane through a cabinet's top 2.8 m away and a seat's and a
  // board's at other heights lies 2.3 cm above the top (rooms 5065), and what stands on
  // the top stands on nothing. false: off (before session 36).
  bool support_fit_height_alone = true;
  // ... on the pixels whose neighbourhood (5 x 5 grid steps) faces within this angle of
  // the found plane's normal: a vertical face in the band (a table's apron seen from just
  // above its height) lies to one side of the surface. 0: every pixel (session 18).
  double support_fit_facing_deg = 45;
  // ... and only when it lies nearer the pixels than the found plane does by their median
  // distance in depth noise units (least median of squares: a chair's seat in a far
  // table's band leans the fit, and its standard errors do not show it). false: off.
  bool support_fit_median_test = true;
  double min_support_area_m2 = 0.04;
  // A later plane keeps only its regions of which some part is seen from above: a
  // region crossed by its height band on a vertical face (a cabinet's front at a chair
  // seat's height) is no part of that support, and its reach would take the cabinet's
  // top 5 cm above the seat for the seat's noisy edge (fresh rooms 9723: the top not
  // found, the torus on it given to the floor, the cabinet reported a prop). false: every
  // region that passed the tests (before session 36).
  bool support_regions_seen_only = true;
  // ... and lie at least this far above or below the earlier supports,
  double min_support_gap_m = 0.06;
  // ... where they lie within reach (in the plane) of an earlier support's regions: a
  // band nearer than min_support_gap_m in height is that support's noisy edge only where
  // the depth noise can put it, support_gap_reach_sigmas of the camera's axial sigma at
  // the pixel's depth along its ray, and no less than support_gap_reach_m (the cells'
  // side): 2 to 4 cm up to 2.2 m, 6 to 8 cm at 3.5 m. Farther away it is another surface
  // (a shelf's board 5 cm above the table's top, 10 cm behind its far edge). 0: everywhere
  // (before session 10). support_gap_reach_sigmas 0: the cells and their neighbours
  // alone (10 to 20 cm with the cells of 0.1 before session 24).
  double support_gap_reach_m = 0.02;
  double support_gap_reach_sigmas = 3;
  // A region near in height is an earlier support's noisy edge or what stands on it (an
  // object's top) when at least this share of it lies within that support's reach or
  // over its hull: one mostly beyond both is another surface whose end comes near (a
  // board beside the next section's), unless it meets the floor without a step (the
  // floor bent by the sensor's distortion at the image's corners). 0: any part in reach
  // (before session 25).
  double support_edge_min_share = 0.5;
  // It meets the floor without a step where, in the median over neighbouring pixels on
  // surfaces facing up, one its and one the floor's, their heights differ by less than
  // this many axial-noise sigmas (a step's face, joining the two heights, faces
  // sideways). 0: never (every region mostly beyond the floor's reach stays).
  double support_floor_step_sigmas = 3;
  // Only a plane that can be a support (the lowest, or one with a region that holds a
  // support seen from above) takes a region as its edge or as standing on it. false:
  // every plane kept in the search (before session 25).
  bool edges_of_supports_only = true;
  // A later support holds min_plane_points, or its pixels cover at least this share of
  // min_support_area_m2 on its plane (each pixel's footprint at its depth and view
  // angle, (z / fx)^2 / cos): a shelf's board 2 m away seen at a grazing angle is a
  // tenth of a square metre in 1,000 to 1,900 pixels, where min_plane_points is a count
  // for a table a metre away. Half: the objects on a board hide part of it, and the
  // hull (min_support_area_m2) still bounds the whole support. 0: the count alone.
  double min_support_seen_share = 0.5;
  // A raised plane's regions that each hold a support and, joined, hide what lies below
  // them (the rays crossing their joint hull end on or above it, as at grazing incidence)
  // are one support: one surface parted by what stands on it. Room 9883: a table 1.4 m
  // away seen from 25 cm above it, its middle hidden by a ball and a bowl, was two
  // supports, the two objects between them in neither hull. false: one support per
  // region (before session 26).
  bool join_parted_surfaces = true;
  // A later support seen from fewer degrees above its plane than this (the camera's
  // height over it against its regions' mean range) is one support of all its regions,
  // as the floor is: at that incidence the Kinect's pattern returns too little from
  // the surface itself (a table top seen level from 26 cm above, 2 m away), so only its
  // edges are seen (its front face, the strip its band cuts across the wall behind it)
  // and its per-region supports are the few patches that returned. 0: off.
  double grazing_support_deg = 10;
  // ... when less than this share of its regions' pixels is seen from above (its
  // edges, not its surface, make up most of it): a board or box top seen at that
  // angle whose surface does return keeps a support per region.
  double grazing_max_seen_share = 0.5;
  // ... and when fewer than this share of the rays crossing the regions' joint hull see
  // past the plane, and no more than a support's smallest region of them end on another
  // support: a surface hides what lies below it. A table top seen level from 26 cm
  // above has only the wall just below its height behind its far edge (18 to 25 % of the
  // rays); a desk and a cabinet top at one height across a room have the floor between
  // them (office1, 74 %). Half: most of what lies behind a surface is hidden by it.
  double grazing_max_through_share = 0.5;
  // Supports whose nearest point is farther from the camera are not used.
  double support_reach_m = 3.5;
  // Whose objects are reported: every support within reach (all), or only the
  // nearest, the highest, the largest, or the one named by support_id ("s2").
  SupportSelection supports = SupportSelection::all;
  std::string support_id;
  // A support whose hull spans more than this is furniture (floor, table, desk,
  // shelf): its surface is never an object's. A smaller one may be an object's top
  // (a box, a seat): its surface stays part of the object under it.
  double furniture_area_m2 = 0.25;
  // A cluster below a support and inside its hull, narrower than this share of the
  // support's width across the view, stands under it (a table's leg, a chair's base):
  // not an object. One as wide as the support is the object whose top the support is
  // (a storage box, a stool) and is kept.
  double under_width_share = 0.5;
  // ... when it stands on the lowest support (the floor): legs and chairs' bases stand
  // there. What stands on a raised support under a higher one is that support's content
  // (a shelf's lower board under its upper one, a desk under its hutch). false: the
  // rule on every support (before session 9).
  bool legs_on_lowest_only = true;
  // ... unless it is seen ending more than this far below that support: a leg rises to
  // the support's underside (under the top's thickness and an apron, a few cm to a
  // hand's width), so whatever lies just above its top in the image is that support,
  // nearer, or its front edge. Where the view passes over its top to the floor or the
  // wall behind (top_seen_ending), lower, it ends there: a ball, a bin or a bottle
  // standing under the table. 0: the rule whatever lies above (before session 26).
  double leg_top_reach_m = 0.15;
  // Looking up from a cluster's top for the support that hides it, a pixel as near as
  // the top lies within the clustering tolerance of it, or within this many sigma of two
  // raw returns' difference (sigma_z sqrt 2) where that is wider: a leg cut by a seat's
  // band 2.65 m away has its own next pixels 2 to 4 cm behind its top (held-out 5035).
  // 0: the clustering tolerance alone (before session 29).
  double top_look_noise_sigmas = 3;
  // A body whose top holds objects is furniture (a cabinet, a shelf) when that top
  // stands at least this far above the body's own support: furniture rises to a
  // working height, while a box a can stands on is a prop of hand size (stacking).
  double furniture_min_height_m = 0.3;
  // ... or at any height when the body's lower half is unseen and the view passes under
  // it (the first pixel below its lowest one farther, in most of its columns): a shelf's
  // lowest board 25 cm up on side panels outside the cluster (fresh rooms 9920, 10069).
  // A box a can stands on shows its front down to its own support. false: off.
  bool board_when_seen_under = true;
  // So is a body rising that far whose top is no support found (a cabinet seen level,
  // its top at a grazing angle) when a cluster on the same support has its lowest point
  // at that top's height, within this many cluster tolerances (the noise of either),
  // over its width and behind its front: its top's pieces or what stands on it
  // (session 11). 0: off.
  double on_top_noise_factor = 2.0;
  // ... and when the body is at least this wide across the view: furniture holds things
  // on a top wider than a hand spans; a prop as tall (a bottle, a tall box) is
  // narrower, and its top's rim comes apart from its front just as a cabinet's top does.
  double furniture_min_width_m = 0.3;
  // A cluster rising at least furniture_min_height_m above its support yet narrower
  // across the view than this share of that height is a leg or a pole, not a prop: a
  // free-standing thing that slim tips over past atan(ratio) (0.15: 8.5 degrees).
  double min_stand_ratio = 0.15;
  // A cluster reaching down to its support whose top is the height band's top in at
  // least this share of its image columns, its surface running on above the band there,
  // is furniture cut by the band (a wardrobe, a cupboard, a chair's back), not a prop:
  // a prop's top ends inside the band and the wall behind it is a depth step away. Half:
  // a cut front continues in nearly every column (depth noise and dropout lose some),
  // a prop's top meets the band's top in none. 0 turns the rule off.
  double cut_top_share = 0.5;
  // A cluster whose foot runs on, with no depth step, into furniture the band cut (the
  // rule above) is that furniture's part above the band, which a raised support's reach
  // took: a chair's back seen from behind, rising past the floor's band beside its seat
  // (unseen rooms 7001). What stands on a support has the support below its foot (or the
  // object it stands on); a ball over a table's edge runs on into its own lower part,
  // which no band cuts (furniture_rules.h, foot_on_cut_body). false: off.
  bool drop_above_band_cut = true;
  // A support's front edge (a table top's, a shelf board's thickness) is at most this
  // thick: under a nearer support, the look-up from a cluster's top for that support's
  // surface runs on across edge pixels this far (tops are 2 to 5 cm thick; at 60 cm the
  // Kinect sees a 3 cm edge in ten grid rows, more than the six looked up before).
  double support_edge_m = 0.06;
  // A cluster whose top, in most of its columns, meets something nearer to the camera
  // (a shelf's board, a seat, a nearer object) is flagged partial: no one sees where it
  // ends (the wall under a shelf's board is no prop). false: only a nearer support's
  // surface hides a top (the rule before session 8).
  bool partial_when_top_hidden = true;
  // A cluster whose lowest point lies more than this above its support, its foot hidden
  // by something nearer in most of its columns, is flagged partial too: no one sees what
  // holds it up at furniture height (a chair's seat behind its back seen from behind, a
  // seat behind the table's top). 0.3: furniture's height (furniture_min_height_m); a
  // prop behind a nearer one shows its upper part from lower down (furniture_rules.h,
  // foot_hidden_high). 0: off.
  double hidden_foot_min_height_m = 0.3;
  // ... and at any height above its support's band when what hides its foot is a higher
  // support's top (furniture_rules.h, foot_behind_higher_support): a shelf's board or
  // side behind the table, a box on the floor behind a cabinet. A prop behind a prop
  // keeps the 0.3 above. false: off.
  bool partial_when_foot_behind_higher = true;
  // A cluster the view passes under (below its lowest pixel, in most of its columns, lies
  // something farther) whose lowest point is higher above its support than its own
  // shadow along the view reaches (its width times the view's slope there) is flagged
  // partial: nothing of its own holds it up, and no one sees what does (a shelf's board
  // 25 cm up in front of the wall, a desk lamp's head). A bowl wide end up hides its foot
  // in that shadow and stays whole. Also counts such columns with the hidden ones in
  // hidden_foot_min_height_m's rule (furniture_rules.h, hangs_seen_under). false: off.
  bool partial_when_seen_under = true;
  // ... and so is one the view just under which meets, in most of the middle third of
  // its columns, something behind the whole cluster standing higher above its support
  // than this many of the support's bands at its depth: a body standing on its support
  // hides its foot under its middle, so that view reaches the support first
  // (furniture_rules.h, view_under_meets_raised; a shelf's board front showing the wall
  // under it). 0: off.
  double seen_under_raised_bands = 2;
  // A cluster lying on the plane fitted to its support's own pixels around it (nine in
  // ten of its points within the support's band at their depth, min_height_m at least,
  // above it) is a piece of that support's
  // surface, not a prop: the support's plane, one fit over its whole band, tilts, and a
  // strip of a table's near edge stood above it (furniture_rules.h, lies_on_own_support).
  // false: off.
  bool support_slab_check = true;
  // A cluster that is one upright flat face, spread along its normal by at most this
  // many times the camera's axial noise at its depth, whose lower end something nearer
  // hides, is flagged partial: a chair's back or a cabinet's side rising behind the
  // table, whose depth and foot no one sees (a flat face spreads by the noise alone, 1.0
  // to 1.2 times; a box 10 cm deep seen from above, 1 m away, 8 times). A face whose foot
  // is seen stays whole (a laptop's lid, a box seen face-on from afar). 0: off.
  double panel_noise_factor = 2.0;
  // ... or by at most this many metres: a piece of furniture is flat to about half a
  // centimetre, beyond what a quieter camera than the Kinect sees of the noise (a
  // chair's back 1.5 m away seen from behind spreads 4.5 mm, under a time-of-flight
  // camera's 1.4 mm sigma). 0: the noise alone.
  double panel_flat_m = 0.005;
  // ... and one whose foot is seen but which is at least this share as wide, along its
  // face, as the raised support it stands on (that support's seen hull along the same
  // line) is flagged partial too: a prop stands on a surface with room beside it, and a
  // face across the whole surface is that furniture's (a chair's back on its seat, 40 to
  // 48 cm on a seat as wide). Not asked on the lowest support (the floor), which runs on
  // unseen. 0: off.
  double panel_span_share = 0.8;
  // A cluster whose face runs on below the plane of its support's own pixels around it, by
  // more than this many times the height noise there (sigma_z times the ray's slope
  // against the plane) and 3 mm, and then meets that support's surface nearer to the
  // camera, in most of its columns, is flagged partial: it stands lower, behind the
  // support's far edge (a chair's back behind the table, 1.5 to 3.3 m away), and no one
  // sees its foot. What stands on the support ends at its surface (furniture_rules.h,
  // runs_below_support). 0: off.
  double below_support_sigmas = 3.0;
  // ... or meets, nearer, what stands on that support in front of its edge (a point more
  // than min_height_m above its plane): a chair's back behind the table 3.6 m away, the
  // objects on the table hiding the table's edge below it (rooms 5088). What stands on
  // the support ends at its surface, and a box stacked flush on another runs on down to
  // the floor, below its support. false: the support's surface alone.
  bool below_support_ends_at_objects = true;
  // A cluster on a raised furniture support (its seen hull above furniture_area_m2) is
  // flagged partial when, in most of its columns, that support's surface (its regions on
  // its plane) ends less than this many clustering tolerances (the depth noise along
  // the view) behind its foot: what stands on a surface has the surface under its whole
  // depth, so it stands at or past the far edge (a chair's back right behind a table
  // 3.7 m away, its foot hidden by the edge at the table's height). Not asked on the
  // floor, which runs on unseen under everything, nor on a smaller support, whose seen
  // part is a fragment with edges of its own. 0: off.
  double edge_room_factor = 1.0;
  int pixel_stride = 2;             // plane search works on every n-th pixel
  // The hull of the support's visible part is extended to the camera's foot on the
  // plane (objects in front of the visible floor hide the floor under them).
  bool hull_to_camera = true;
  // The hull is grown by this margin: a floor seen between furniture still holds
  // the objects standing beside its visible part (office1's storage box).
  double hull_margin_m = 0.0;
  // The lowest support (the floor) grows by this much: it runs on under what stands
  // on it beyond its visible patches. 0 keeps the paper's hull.
  double floor_margin_m = 1.0;
  // An object stands with its centre over its support (else it tips), so it reaches past
  // the support's edge by at most its half width: pixels in the height band up to this
  // far beyond the hull join a cluster grown from inside it (an object across a table's
  // edge), and start none; not past the far edge (what hangs there is hidden behind the
  // object). Half the widest prop's footprint. 0: off.
  double overhang_margin_m = 0.1;
  // A small support's seen part (a shelf's board seen at a grazing angle, its top
  // between what stands on it) ends where the view of it does, not where it does: what
  // stands on it hides the rest. Band pixels over no support's hull or reach, up to this
  // far around such a part, form clusters of their own (joined with no other), kept when
  // the cluster's lowest point lies on the plane and its surface is not seen running on
  // below the plane beneath that foot (a wall behind the board is; a cup standing on it
  // is not: the board, nearer, lies under its foot), when it ends below the height band's
  // top, and when it is not one upright flat face (upright_panel: there, the shelf's back
  // between two boards). Not on the lowest support or on furniture, whose seen hull is
  // the surface's own. 0.4: a shelf's depth. 0: off.
  double seen_part_reach_m = 0.4;
  // A cluster stands on the support its lowest point lies on: when that point lies on a
  // higher support's plane (in its band), within its reach (the hull grown by
  // overhang_margin_m) and not past its far edge, the cluster is that support's, not
  // the lower one's whose hull holds its other pixels (a ball over the table's edge, an
  // object at the end of a board's seen part). false: the nearest support below each
  // pixel whose hull it stands in.
  bool support_from_foot = true;
  // Clusters whose surface continues above max_height_m (walls, cupboards, people)
  // are not objects on the support: dropped when true.
  bool drop_cut_clusters = true;
  // It continues above when its pixels join pixels above the band on its surface at least
  // 8 times and a fiftieth of its pixels, or, when fewer, this share of its grid columns:
  // a tall thin post joins along its narrow top edge alone (fresh room 9543: a post 7 cm
  // square, 59 cm of it in the band, joined 12 times against the 16 its pixels asked).
  // 0: the pixels' share alone.
  double cut_join_column_share = 0.5;
  // The band over a support where a pixel is its surface, not an object's, is the depth
  // noise along the pixel's ray seen across the plane: plane_noise_factor sigma_z
  // |n . ray|, times the support's own spread in those units (a robust sigma of its
  // pixels' heights, at least 1: a plane fitted off, or a surface the sensor bends, shows
  // more), between plane_distance_m and the band above. A table seen at 25 degrees moves
  // a point 0.42 sigma_z off its plane: 2.4 m away, its objects' lowest 1.2 cm go in the
  // band, not 2.4 cm. false: plane_noise_factor sigma_z whatever the view (before
  // session 27).
  bool band_along_ray = true;
  // Prism: objects between these heights above the plane, inside its hull.
  double min_height_m = 0.012;
  double max_height_m = 0.6;
  double max_depth_m = 4.0;  // farther points are ignored (Kinect range)
  // Clusters: grid neighbours closer than this in 3D join (or than cluster_noise_factor
  // times the depth noise where that is wider: 3.9 cm at 3.5 m, so a far wardrobe is
  // not cut into slices); tiny clusters are dropped.
  double cluster_tolerance_m = 0.02;
  double cluster_noise_factor = 2.0;
  int cluster_window_px = 2;   // neighbours searched within +-n pixels (bridges dropouts)
  // A dark surface's fragments under the size floor are joined across runs of missing
  // depth up to this many pixels (dropout_join.h). Pixels, not metres: the sensor judges
  // each pixel's return alone, so the runs between returned pixels follow the share of
  // pixels kept, whatever the depth. 8: where a dark face keeps a quarter of its pixels
  // a run longer than 8 is left in one direction of ten (0.75^8); 8 pixels span 1.5 cm
  // at 1 m and 3.8 cm at 2.5 m, under the 5 cm of the smallest object measured, and the
  // join asks the points to lie as close in 3D as the gap's width at their depth.
  int dropout_max_gap_px = 8;
  // Every fragment under the size floor is offered to the join, not only those under
  // the grid's coarse half of it: on a dark surface few of a grid pixel's block return,
  // so a fragment of half the floor or more still falls under it (session 31; false:
  // as before).
  bool dropout_join_to_floor = true;
  // Full-resolution points at 1 m; farther clusters need fewer (a surface's pixel
  // count falls with the square of depth), never fewer than min_cluster_points_far:
  // a 6 cm ball 2 m away shows about 60 points above the band (80 dropped it). Such
  // small clusters are partial (min_whole_points) and do not vote.
  int min_cluster_points = 300;
  int min_cluster_points_far = 40;
  int max_cluster_points = 250000;
  // MLS: local plane fit within this radius, points projected onto it. 0 disables.
  double mls_radius_m = 0.012;
  int mls_window_px = 4;
  // Points whose smoothed surface is seen at a grazing angle (|cos| below this) are
  // veil points between an object's edge and the background: left out of the fits.
  double min_view_cos = 0.2;
  // A cluster with at least `part_share` of its points inside a bigger object's fitted
  // solid grown by `part_margin_m` is a part of it cut off by a depth edge (a bottle's
  // handle): it joins that object, which is fitted again. 0 disables.
  double part_margin_m = 0.015;
  double part_share = 0.6;
  // A piece seen hanging (the view passes under it, higher than anything of its own
  // hidden there could hold it up) with part_share of its points within this of a bigger
  // object's solid is part of it: a mug's handle, cut off its body at the crease where
  // it meets the wall, floats beside it. 0 disables.
  double part_hang_reach_m = 0.04;
  // A part rising from an object's top is no object standing on it (stacking): the
  // object's surface just beyond its foot falls away from it more steeply than
  // `neck_min_slope_deg` (a bottle's neck on its shoulder; a lid is level to the noise),
  // and it is at most `neck_max_width_share` of that object's width across its foot
  // (one as wide has only the lower object's wall around it). It joins that object as
  // its part. A share of 0 disables.
  double neck_min_slope_deg = 20;
  double neck_max_width_share = 0.6;
  // ... unless the bigger object's extent is unseen (cut by the image border, or hidden
  // in half: the partial flag's test): its primitive spans what is seen of it, not its
  // solid (a shelf's side and board edge as one box span the board and what stands on
  // it). false: any bigger object holds parts.
  bool unseen_hold_no_parts = true;
  // A grown object whose refit is another shape, explaining its points less than it did
  // alone by more than this, took a neighbour's piece (one cut off a touching body), not
  // a part of its own (a handle leaves its shape as it was): it and its parts stay as
  // they were. The occlusion join's slack. 1: never.
  double part_fit_slack = 0.05;
  // Clusters split at concave creases and depth steps (object_segmenter.h).
  SegmenterParams segment;
  // A cluster whose shape explains less than this share of its points is tried as two
  // touching bodies, kept when two primitives explain it better by the information
  // criterion (touching_split.h). One object's primitive leaves out its handle or the
  // veil at its edges (0.82 for the real milk frame's bottle with a handle, 0.88 and more
  // for a box 0.58 m away and nyu_basement's upper bin), two bodies under one leave out
  // one of them (0.4 to 0.84: a ring against a flat bowl 1.1 m away under one box, 0.84).
  // Every cluster tried costs its refits, kept or not: between touching_two_feet_coverage
  // and this gate only clusters standing on two feet are tried (below), so the milk
  // frame's bottle (12,000 points, 0.85) costs nothing (tried: its shapes 3.4 -> 6.8 ms).
  // 0: off.
  double touching_max_coverage = 0.85;
  // Each part of a cut is explained by its own shape over at least this share of its
  // points (a part explained worse is no body of its own: a wall's patch, a piece of
  // furniture). A question apart from the gate above: one value for both made a wider
  // gate ask more of the parts, and a dark cup's part (0.84) lost its cut.
  double touching_part_coverage = 0.8;
  // A cluster explained over at least this share, under the gate, is tried only when it
  // stands on two feet: its foot (its lowest quarter) narrows between the cut's two means
  // and its front, seen from the camera, recedes between them (touching_split.h,
  // stands_on_two_feet), or no point of its foot is seen though it reaches into the lower
  // half of its height (bodies seen from above that hide their feet: nothing tells one
  // body from two). Two bodies side by side each show their own front; a bottle's
  // handle rises from its side, and its foot seen as a ring's front arc is one front.
  // 1: every cluster under the gate is tried (0.8 and 1 were the defaults before
  // session 37).
  double touching_two_feet_coverage = 0.8;
  // ... or whose foot is seen in two pieces: between the means a run of bins holding no
  // point of it, whose chance under the foot's own sampling (a far foot leaves single
  // bins empty) is below exp(-touching_gap_evidence). 0: the front's notch alone (before
  // session 38; fresh rooms 8084's sphere against a tin 3 m away stayed one object).
  double touching_gap_evidence = 6.9;  // ln(1000)
  // ... and refitted in two when what its primitive leaves out lies on one side of the
  // cut, or when its footprint narrows between the cut's two means to under this share
  // of its width at the narrower one: a convex body's footprint never narrows between
  // two of its points, two touching ones narrow to their contact. 0: the one-side test
  // alone.
  double touching_waist_share = 0.7;
  // ... and when that cut is not kept, cut along what the one primitive leaves out (the
  // means halve the larger of two bodies that differ in size: a flat bowl against a box
  // of twice its pixels). false: the means' cut alone.
  bool touching_misfit_cut = true;
  // ... and when what the one primitive leaves out lies above or below the rest, not
  // beside it, the cut is level there: one body standing on the other, too far for the
  // segmenter's crease test (segment.level_min_height_m tall each; touching_split.h).
  bool touching_level_cut = true;
  // An upright cluster its one primitive explains well (touching_max_coverage or more;
  // any, where the segmenter's crease test is blind) whose outline steps in width at one
  // height is cut level there, kept as the level cut is (a far stack that one cone
  // explains whole; touching_split.h).
  bool touching_width_step = true;
  // Each of the two parts shows at least the pixels of a body this wide at its depth
  // (the disc it spans in the image): the smallest object reported, whose pixel count
  // falls with the square of its depth.
  double touching_min_part_size_m = 0.05;
  // An object whose base sits on another object's top is fitted on that top face.
  bool stack_on_objects = true;
  // Pieces of one shape either side of a nearer object, which one primitive explains
  // together, are one object seen past an occluder.
  bool join_occluded = true;
  // Pieces of one shape either side of a raised support's plane, the upper on that
  // support and the lower right under it in the image on a lower one, which one
  // primitive explains together, are one object standing on the lower support (a bottle
  // beside a box whose top is a support; occlusion_join.h, join_across_support_plane).
  bool join_across_supports = true;
  // Objects with pixels within border_px of the image edge (cut by it; the edge of the
  // rows and columns that hold depth) or with fewer than min_whole_points pixels are
  // partial: reported, but they do not vote.
  int border_px = 4;
  // ... and so are objects whose foot runs off the image's bottom edge unseen: their
  // lowest pixels within border_px plus the rows of their support's band (an object's
  // lowest min_height_m is in the band, no cluster pixel: 13 rows half a metre away), or
  // with no depth below them down to that edge (a dark or too-near foot), in three
  // columns or more (furniture_rules.h, foot_cut_by_bottom). false: border_px alone.
  bool foot_at_border = true;
  // ... and so are objects whose fitted foot (the salient fit's outline within the
  // support's band above its lowest point) projects within border_px of any edge of the
  // image's depth or beyond it: the band's pixels are no cluster pixels, so a flat cone's
  // foot ring can run off the side unseen (furniture_rules.h, fitted_foot_off_image).
  bool fitted_foot_at_border = true;
  // ... and so are objects running into the sensor's near blind zone, which returns no
  // depth: three pixels or more nearer than sensor_min_range_m + near_cut_margin_m beside
  // a pixel without depth (a bowl's near rim 40 cm from the camera). The margin is a
  // pixel's depth step on a surface seen at 80 degrees plus three sigma_z there. The
  // default range is the Kinect's near mode; set your sensor's (0: off).
  double sensor_min_range_m = 0.4;
  double near_cut_margin_m = 0.01;
  int min_whole_points = 400;
  // The focal length, in pixels, that the pixel-unit parameters are given for: the
  // Kinect's at 640 x 480. A camera of focal f sees a surface over f / this times the
  // pixels along a line and its square in area (a 320 x 240 stream: a half and a
  // quarter; a 1280 x 720 RealSense, about 640 px: 1.2 and 1.5), so the scan takes the
  // pixel counts (min_plane_points, min_cluster_points, min_cluster_points_far,
  // max_cluster_points, min_whole_points, segment.min_object_points,
  // shape.min_foot_seen_pixels) times that square and the pixel spans (pixel_stride,
  // cluster_window_px, mls_window_px) times the ratio, at least 1. The ratio is taken
  // from the nearer end of the Kinect calibrations' range, 1/1.15 to 1.15 of this (TUM's
  // 517 to 535 px, NYU's 583): within it the parameters hold as given. Left as they are:
  // what follows the sensor's pixels themselves (dropout_max_gap_px: runs of dropped
  // pixels; border_px; segment.min_arm_px: 3 x 3 pixel means). 0: no scaling (before
  // session 38: a 320 x 240 frame found 60 % of the rooms' objects 1.5-2.5 m away right,
  // 93 % at 640 x 480).
  double pixel_units_focal_px = 525;
  ShapeRecognizerParams shape;
  // Flat surfaces for virtual panels (ScanResult::surfaces). Off for scans that match no
  // plane primitive (a session whose spec has none, benchmarks): surfaces stay empty.
  bool plane_candidates = true;
  PlaneCandidateParams planes;
  // Worker threads for the per-cluster stages (smoothing, shapes); results do not
  // depend on it.
  int threads = 2;
};

// Reads `key value` lines (# comments); errors carry file:line:col. Unknown keys are
// errors too (a misspelt key silently ignored would change the scan).
Result<ScanParams> parse_scan_config(std::string_view text, std::string_view origin);
Result<ScanParams> read_scan_config_file(const std::filesystem::path& path);
// The effective up vector after camera tilt.
Vec3 effective_up(const ScanParams& params);
// "all", "nearest", "highest", "largest" or a support id ("s2"); errors name the choices.
Result<ScanParams> with_support_selection(ScanParams params, std::string_view choice);

// One object as found in the frame, for overlays and tracking.
struct ScanCluster {
  std::vector<int> pixels;     // indices into frame.points
  std::vector<Vec3> points;    // smoothed points used for the fits
  ObjectShape shape;
  Plane support;               // the plane it stands on
  int on_object = -1;          // index of the object whose top it stands on, -1: the support
  SupportAround around;        // its support's surface seen around it, while its shape is
                               // fitted (the shape's free space); empty in a ScanResult
};

// A support found in the frame, with its hull (on its plane) for overlays.
struct ScanSupport {
  SupportSurface surface;
  std::vector<Vec3> hull;
  double area_m2 = 0;     // of the hull
  double distance_m = 0;  // from the camera to its nearest point
  bool furniture = false;  // hull above furniture_area_m2
  bool selected = false;   // its objects are reported
};

struct StageTime {
  std::string name;
  double ms = 0;
};

struct ScanResult {
  // Selected supports, the first as `support`, and objects p1, p2, ... left to right.
  PhysicalScene scene;
  Plane plane;                       // the first selected support
  std::vector<Vec3> hull;            // its convex hull, on the plane
  std::vector<ScanSupport> supports;  // every support found, selected or not
  std::vector<ScanCluster> clusters; // same order as scene.objects
  // Flat surfaces for virtual panels (plane_candidates.h), apart from scene.objects.
  std::vector<PhysicalObject> surfaces;
  int plane_inliers = 0;
  std::vector<StageTime> stages;     // plane, prism, clusters, mls, shapes
};

// Errors: an empty or all-invalid frame, no near-horizontal plane in it, or no
// support the selection accepts (an unknown id names the ones found).
Result<ScanResult> scan_frame(const Frame& frame, const ScanParams& params = {});

// Left-to-right order of objects and their ids p1, p2, ...: by the image column of the
// cluster's centroid (ties by row), so repeated scans of one frame agree.
void order_and_name_objects(ScanResult& result);

}  // namespace annex
