#pragma once
// Flat surfaces a virtual panel (a plane primitive: a screen, a keyboard, buttons) may
// be laid on, from one scan: each box's top face (a carton, a book lying flat), each
// slab's broad face (a laptop's lid), and
// each selected support's largest free rectangle within reach (the table where nothing
// stands, on the user's side).
// They are reported apart from the scan's objects (ScanResult::surfaces), so a plane
// never changes the objects' votes; scene_with_surfaces() gives the matcher both.

#include <vector>

#include "annex/common/physical_scene.h"
#include "annex/runtime/frame.h"

namespace annex {

struct ScanResult;
struct ScanParams;

struct PlaneCandidateParams {
  // A rectangle with a side shorter than this holds no panel a fingertip presses.
  double min_side_m = 0.05;
  // Free regions keep this clearance from every object standing on the support
  // (a hand pressing the panel must not hit the mug beside it).
  double clearance_m = 0.03;
  // Side of the occupancy grid's cells on a support's plane.
  double cell_m = 0.01;
  // A box's top face counts when its normal is within this angle of the support's up
  // and at least this share of the box's points lie on it (the face was seen).
  double max_face_tilt_deg = 25;
  double min_face_share = 0.1;
  // A box thinner than this share of its broad face's shorter side is a slab (a book,
  // a tablet, a laptop's lid): its broad face counts whichever way it faces.
  double slab_ratio = 0.25;
  // A support's free rectangle lies where a hand reaches it: within this distance (on
  // the plane) beyond the free surface nearest to the camera, the edge the user stands
  // at (a forearm and hand, 0.5 m). When no rectangle of min_side_m fits there, the whole
  // free surface is searched.
  double reach_m = 0.5;
};

// Candidates named `<object>.top` (a box's top), `<object>.face` (a slab's broad face
// tilted more than max_face_tilt_deg) and `<support>.free`, each one plane primitive
// (size_x >= size_y, axis its normal pointing up, x_axis along size_x, center the
// rectangle's centre), point_count the pixels seen on it. `frame` is the grid the scan
// worked on.
std::vector<PhysicalObject> find_plane_candidates(const Frame& frame, const ScanResult& scan,
                                                  const ScanParams& scan_params,
                                                  const PlaneCandidateParams& params = {});

// The scan's scene with its flat surfaces appended to the objects (ids unique), for
// matching virtual panels: physical indices past the objects are surfaces.
PhysicalScene scene_with_surfaces(const ScanResult& scan);

}  // namespace annex
