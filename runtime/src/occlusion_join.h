#pragma once
// An object seen in two pieces either side of a nearer one (a box behind a standing can,
// a can lying behind a box) is one object: pieces of the same shape on the same support
// whose image gap is covered by a nearer object, and which one primitive explains
// together, are joined.
// Private to the scanner.

#include <functional>
#include <vector>

#include "annex/runtime/frame.h"
#include "annex/runtime/scanner.h"

namespace annex {

struct OcclusionJoinParams {
  // The occluder must be this much nearer than both pieces.
  double min_occluder_gap_m = 0.02;
  // The joint fit may explain this much less than the worse piece's own fit.
  double coverage_slack = 0.05;
  // A pixel in the gap this close to the support is the table: the pieces are apart.
  double support_band_m = 0.015;
  // Pixels of no object, above the table and not behind the pieces, may be at most this
  // share of the segment between them (the hidden object's edge pixels, which no
  // cluster kept).
  double max_unclaimed_share = 0.1;
};

// Where a cluster lies in the image and how far: its pixels' mean image position and
// median depth. Reads only the cluster's pixels (the scanner finds them beside other
// work).
struct OccludedPiece {
  double u = 0, v = 0, z = 0;
};
OccludedPiece describe_piece(const Frame& frame, const ScanCluster& cluster);

// clusters: the scan's objects; label: cluster index per pixel (-1 none), kept up to
// date; pieces: describe_piece of each cluster; refit(cluster, id) smooths and fits a
// grown cluster again. Joined pieces are removed from `clusters`.
void join_occluded_pieces(const Frame& frame, std::vector<ScanCluster>& clusters,
                          std::vector<int>& label, std::vector<OccludedPiece> pieces,
                          const std::function<void(ScanCluster&, int)>& refit,
                          double min_coverage, const OcclusionJoinParams& params = {});

// An object standing beside a raised support, taller than it (a bottle beside a box
// whose top is a support), is cut at that support's plane: its pixels above the plane
// and within the raised support's hull are that support's candidates, those below the
// lower one's. Two such pieces, the upper on a raised support and the lower right under
// it in the image (in most of the upper's columns the first pixel below its lowest out
// of the raised support's band, `band` at its depth, is the lower's, within `tolerance`
// plus the band's height of it in depth), of one kind of shape and explained by one
// primitive together (as join_occluded_pieces asks), are one object standing on the
// lower support: joined there. `joined[c]`: the cluster c holds such a joint object (its
// upper piece stood on nothing but that plane; a stack found for it is void).
// refit(cluster, id) as for join_occluded_pieces.
void join_across_support_plane(const Frame& frame, std::vector<ScanCluster>& clusters,
                               std::vector<int>& label, int step,
                               const std::function<double(double z)>& tolerance,
                               const std::function<double(double z)>& band,
                               const std::function<void(ScanCluster&, int)>& refit,
                               double min_coverage, std::vector<char>& joined,
                               const OcclusionJoinParams& params = {});

}  // namespace annex
