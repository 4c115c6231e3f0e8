#pragma once
// Every tunable of the tracker, with the paper's values where the paper gives
// one (Table 1) and documented choices elsewhere (docs/JOINTS.md). Fixed for a
// run: Tracker reads them, never writes them.
#include "tracker/types.h"

namespace vts::tracker {

// Closed interval [min, max]; a process value is accepted when it lies inside.
struct Range {
  double min = 0.0;
  double max = 0.0;
  bool contains(double v) const { return v >= min && v <= max; }
};

// Step 1: outlier elimination (the paper names the step, not the method).
struct OutlierParams {
  bool enabled = true;
  // Longest run of consecutive points that can be removed as one cluster.
  int max_cluster_points = 4;
  // A run whose farthest point lies more than this off the line its
  // neighbours define is an outlier cluster...
  double threshold_mm = 0.3;
  // ...provided support_points neighbours on each side lie within support_tol_mm
  // of that one line (so a real corner, whose two sides do not share a line, is
  // never removed).
  int support_points = 3;
  double support_tol_mm = 0.1;
  // A cluster at the start or end of a run (the profile is cut at jumps) can
  // have made that jump itself: it is removed when support_points + 1 points
  // beyond the cut and as many after it share one line (within
  // support_tol_mm) that it leaves (by more than support_tol_mm across a
  // jump, threshold_mm across invalid columns), and its step back onto the
  // line is at least half the jump (a wall seen in a gap joins its plate with
  // a short step).
  bool run_end_clusters = true;
  // An island is kept as a piece of a steep surface only if the next point
  // beyond the cut continues its line past the island's end (the line of a
  // short island passes near points beside it too).
  bool islands_continue_ahead = true;
};

// Steps 2 and 3: split and merge, the paper's Table 1 plus the rule that cuts
// the profile at discontinuities before splitting.
struct SegmentParams {
  double split_threshold_mm = 0.4;  // t_split: split while d_max exceeds this
  int split_interval = 2;           // s_int: d_max looks at every s_int-th point
  int min_segment_points = 8;       // s_min: regions smaller than this are not split
  int max_merge_gap_points = 10;    // g_max: merge across fewer missing columns than this
  double max_merge_angle_deg = 15.0;  // alpha_merge: merge lines closer in angle than this
  // Not in Table 1: merged neighbours must also be offset by less than this
  // (or 3 rms of their fits, if larger; each one's facing end point from the
  // other's line), or parallel plates with a small step (a butt joint's
  // mismatch) would merge.
  double max_merge_offset_mm = 0.2;
  // A step between consecutive points is a jump (the profile is cut there
  // before splitting) if it is longer than break_min_mm and longer than
  // break_ratio times the shorter of its neighbouring steps. Runs of invalid
  // columns always cut.
  double break_min_mm = 0.3;
  double break_ratio = 4.0;
  // At a boundary between two segments a point moves to the neighbour whose
  // line it fits better, if it lies within this (or 3 rms) of that line. End
  // points farther than this (or 4 rms) off their segment's line are detached
  // (step 4; with TrackerParams::noise_aware_detach, only beyond the
  // tracker's surface_tol_mm too).
  double fit_tol_mm = 0.02;
  // The rough split (TrackerParams::split_rough_segments) asks each side of
  // its point to fit a line at least twice as well as the whole. At a step
  // between parallel lines (a butt's mismatch below t_split) the point there
  // lies on one of them only: true, each side is tested with it on the side
  // it fits (a 0.28 mm step over 45 mm of plate at noise 0 failed by 1 %
  // with it on the wrong side, and the step went unseen). false: on both.
  bool rough_step_either_side = true;
  // Where the rough split's test fails at the region's farthest point from
  // the chord, it is tried where two lines, one through each side, fit the
  // region best (least squares over every place), and cuts there if the
  // two lines are parallel within rough_step_max_angle_deg: a step (a
  // butt's mismatch) on a wavy surface, whose farthest point from the chord
  // waviness can put a millimetre away. Corners are cut at the farthest
  // point as before. false: only there.
  bool rough_split_best_fit = true;
  double rough_step_max_angle_deg = 5.0;
};

struct SegmentationParams {
  OutlierParams outliers;
  SegmentParams segments;
  // Image-processing region: profile columns [roi_first, roi_last] are used;
  // roi_last < 0 means up to the last column.
  int roi_first = 0;
  int roi_last = -1;
  // The point every column ray passes through, sensor frame (mm). The vts
  // sensor frame has the laser at the origin, so (0, 0). Used to place plate
  // edges between two neighbouring columns' rays.
  Vec2 ray_origin_yz = Vec2::Zero();
};

// Which of the two fillet plates is the web (the one whose edge may stand off
// the other). Auto: the plate whose edge the profile shows standing off (the
// other plate is seen beyond its line, through the gap); with no gap, the
// second plate in scan order.
enum class WebSide { Auto, First, Second };

struct FilletParams {
  // The plates are also paired across one short segment between them at
  // the root that continues neither (a web's rounded or chamfered bottom
  // edge). false: neighbouring long segments only.
  bool across_edge = true;
  Range angle_deg{45.0, 135.0};  // angle between the plates on the open side
  Range gap_mm{0.0, 3.0};        // true gap: web edge to flange
  WebSide web = WebSide::Auto;
  // With a gap, the web's edge is placed from the last point towards the
  // flange that lies on the web's line (as a butt plate reaches), not only
  // from its long segment's end: noise can cut the web's last points off.
  bool web_reaches = true;
  // Each plate is extended over the long segments beyond it that continue its
  // line (noise can cut a plate in pieces; the piece at the root alone can
  // give a wrong angle), as the corner's faces are.
  bool extend_plates = true;
  // A gap shows as the flange seen beyond the web's line. Besides the flange's
  // long segment and the points removed as outliers, the points kept between
  // the plates (in short pieces) that lie on a plate's line beyond the other
  // plate's line count as that plate's end: a dropout or one noisy point can
  // cut the few flange points seen through the gap off as a short piece.
  bool flange_pieces = true;
  // A plate may be a gentle arc near the root (a pipe's section: the main
  // pipe of a saddle, docs/JOINTS.md "Fillet"). Each plate's points within
  // curve_window_mm of the lines' corner are fitted with a quadratic across
  // its line, and the root is where the plates' curves meet. A plate is
  // curved when its line does not explain it to within curve_rms_sigma
  // noise sigmas (rms) and the quadratic through all its points does
  // (waviness does not), its quadratic term is at least curve_t standard
  // errors (the larger of the noise and the fit's own residual), its radius
  // at least min_curve_radius x the window, and near the root no cubic
  // term is as significant (one wave of waviness).
  bool curved_plates = true;
  double curve_window_mm = 10.0;
  double curve_t = 5.0;
  double min_curve_radius = 5.0;  // in curve_window_mm
  double curve_rms_sigma = 1.5;   // the arc's residual at most this many noise sigmas
};

struct CornerParams {
  Range angle_deg{60.0, 170.0};  // angle between the outer faces through the material
  Range gap_mm{0.0, 3.0};        // between the two plates' outer edges
  // A shallow notch (within a rounding's reach behind the faces) whose
  // flanks meet at a bottom, every column between the faces holding a kept
  // point, is a closed corner's rounded or chamfered edges: read closed, at
  // the faces' apex, alone (false: the closed and the open reading compete,
  // the profile ambiguous when they lie apart).
  bool closed_notch = true;
  // An open corner's edges (its outer faces' meeting with its end faces)
  // from the end faces as seen, at any slant (mitred ends), or, behind a
  // rounding or chamfer with the face unseen, in the interval between its
  // farthest point and the next ray, read at the middle, that interval its
  // uncertainty (false: end faces square to the outer faces, the rounding's
  // and chamfer's points taken as face points; before 2026-11-28).
  bool fit_end_faces = true;
  // Long segments between the two outer faces that continue neither: an
  // open corner's notch, each plate's end face and its rounding or chamfer
  // (each can be a long segment seen close up). More than this only as a
  // closed notch's arcs (closed_notch). 2 before 2026-11-28 (session 31):
  // a gap between chamfered edges with an end face seen had 3 and was
  // never read.
  int max_between = 4;
};

struct LapParams {
  Range step_mm{0.5, 30.0};      // upper plate's top edge above the lower plate
  Range gap_mm{0.0, 3.0};        // upper plate lifted off the lower one
  Range angle_deg{45.0, 135.0};  // upper plate's edge face against the lower plate
  double max_plate_angle_deg = 15.0;  // the two plates must be this close to parallel
  // Upper plate thickness if known (> 0): gives the gap from the step when the
  // edge face is hidden. 0: unknown, gap not measured in that case.
  double upper_thickness_mm = 0.0;
  // Each plate is extended over the long segments beyond it that continue its
  // line (noise can cut a plate in pieces; the piece at the step alone can be
  // several degrees off and fail the parallel test), as butt plates are.
  bool extend_plates = true;
  // Long segments (of at least s_min points) that may lie between the
  // plates, none of them on a plate's line: the edge face, and the upper
  // plate's rounded or chamfered top edge cut in up to two pieces (1: the
  // edge face alone, before 2026-11-28; a top edge's chamfer 2 mm wide is a
  // long segment of its own, and the plates were not paired across it).
  int max_between = 3;
  // The reading's evidence (Matcher::weigh) takes each plate on its own
  // line: an upper plate resting on its edge (on a bead, a burr, a gap at
  // one side) lies 0.5-3 degrees off the lower one, tens of microns off a
  // parallel line within 10 mm, which then left its points unexplained or
  // the plate "curved". false: one direction for both, as the butt's.
  bool tilted_upper = true;
  // The edge face is fitted to the points between the plates that lie on
  // neither line, short of the points next to the upper plate that it
  // reaches over (on its line, as a butt plate reaches): noise cuts the upper
  // plate near its edge into short pieces, and their points off its line
  // were fitted into the face (angle 117 instead of 90 degrees).
  bool upper_reaches = true;
  // With the edge face hidden, the top edge is checked against the points
  // around it (docs/JOINTS.md "Lap"): it lies past the upper plate's last
  // point and its edge preparation's (points between the plates' levels)
  // and short of where the first ray that reached the lower plate beyond
  // it crosses the upper plate's line. A reading is rejected ("uncertain")
  // when such points lie more than edge_past_mm past the edge as read, or
  // when that interval reaches more than edge_interval_mm from it on either
  // side (a rounded, chamfered or shadowed edge: not placed to 1 mm).
  bool check_edge = true;
  double edge_past_mm = 0.5;
  double edge_interval_mm = 1.25;
  // With square edges (TrackerParams::square_edges) the edge face is square
  // to the upper plate: points between the plates on a line more than this
  // far from square are its edge preparation (a chamfer, a rounding), the
  // face hidden below them. A sensor's pitch and yaw shear a square corner
  // by a few degrees.
  double max_face_off_square_deg = 10.0;
};

struct ButtParams {
  Range gap_mm{0.0, 5.0};
  Range mismatch_mm{0.0, 3.0};
  double max_plate_angle_deg = 15.0;  // the two plates must be this close to parallel
  // On noisy profiles missing columns with both plates' ends on one line are
  // weak evidence of a gap (a dropout looks the same), unless the rays found
  // nothing over a run of at least this many consecutive columns: dropouts on
  // a plate are isolated columns.
  int min_hole_columns = 2;
  // Plates found by splitting one merged segment at a hole are extended over
  // the long segments beyond them on their line, as neighbouring plates are
  // (noise can cut the far part short; its own line alone is off in angle).
  bool extend_split_plates = true;
  // A closed joint's rounded or chamfered edges dip less than the split
  // threshold (0.4 mm) below the plates and leave them one segment, with
  // no corner for the step test. A run of at least 3 consecutive points of
  // a segment behind its line by more than the surface tolerance, s_min
  // points or more from either end, is read as the joint, the segment's
  // parts before and after it the plates (false: before 2026-11-28,
  // session 31; a dropout run elsewhere was then read as a tight gap).
  bool dip_in_segment = true;
  // A hole fewer than s_min points from a segment's end or start (noise cut
  // the plate beyond it into pieces, and the merge joined the first piece to
  // the segment across the hole) is a gap candidate when the next (previous)
  // long segment reaches back over the pieces to it.
  bool stub_across_hole = true;
  // Each edge is checked against the points around it, as a lap's top edge
  // is (LapParams::check_edge, docs/JOINTS.md "Square butt"): it lies past
  // the plate's last point and its edge preparation's (the run of points
  // right after it behind its line that drop no more than they run on, as
  // rounded or chamfered edges are read) and short of where the ray of the
  // first point after them (the other plate, an edge face, the gap, or an
  // invalid column: a ray into it) crosses the plate's line; points in
  // front of both plates (a reflection cluster) say nothing. A reading is
  // rejected ("uncertain") when the plate's own points (runs of 3 or more
  // on its line, beyond a dropout or a shadow) lie more than edge_past_mm
  // past an edge as read, or when the interval the track point (the edges'
  // midpoint) can lie in reaches more than track_interval_mm (a false
  // read's distance) from it. Such a reading stays a rival of the others.
  bool check_edges = true;
  double edge_past_mm = 0.5;
  double track_interval_mm = 1.0;
  // Each plate is straight up to its edge preparation: its own points
  // within ConfidenceParams::window_mm of the edge (on its line within 2
  // surface tolerances, short of the opening's reach back from the edge +
  // edge_past_mm: a rounding's or chamfer's points), at least
  // plate_cap_points, that a parabola fits as a cap convex towards the
  // sensor (VGrooveParams::root_bump_t's test: its curvature at least
  // plate_cap_t standard errors from straight given the profile's noise,
  // higher than the surface tolerance above the chord through its end
  // points) are a tack weld's or a bead's crest read as a plate: the
  // reading is rejected as `uncertain` (and stays a rival, as above).
  bool check_plate_caps = true;
  int plate_cap_points = 8;
  double plate_cap_t = 4.0;
};

struct VGrooveParams {
  Range angle_deg{20.0, 120.0};  // included angle between the bevels
  Range gap_mm{0.0, 5.0};        // root opening
  Range mismatch_mm{0.0, 3.0};
  Range depth_mm{0.5, 60.0};     // plate top to root (checked when the tops are seen)
  // A bevel seen at a grazing angle has few points: bevels need only this
  // many (the plate tops need SegmentParams::min_segment_points).
  int min_bevel_points = 4;
  // A bevel seen edge-on and thinned by dropouts can have fewer: a segment of
  // at least two points with its plate top (a long segment) directly on its
  // outer side is a bevel if it has this many points, counting the points
  // removed as outliers between it and the top that lie on its line.
  int min_short_bevel_points = 3;
  // Such a short bevel's plate top may also lie beyond at most two short
  // pieces whose points all lie on the bevel's line or on the top's line
  // (within surface_tol_mm): noise at the top edge of a bevel seen edge-on
  // cuts a short piece off the top, or leaves one across the edge. The
  // pieces' points on the bevel's line and off the top's count for the bevel.
  bool short_bevel_across_pieces = true;
  // A plate top is looked for past long segments within two roundings'
  // reach (6 mm) of the bevel's end that are no top, and past a top no
  // longer than that reach while a longer one follows: a rounded top edge
  // cut into pieces of 8 points or more, some within 30 degrees of the top
  // (false: the nearest long segment beside the bevel only; before
  // 2026-11-28).
  bool tops_past_rounding = true;
  // The plate tops are one plane: a pair of tops more than this far from
  // parallel has taken a bevel or a root face for a top (the nearest long
  // segment beside a bevel), and the reading is made without them (a short
  // bevel keeps the top it needs). The butt's and lap's plates are held
  // to the same angle.
  double max_top_angle_deg = 15.0;
  // The model check of an open root: the rays between its edges go into the
  // opening, where a backing bar or the root faces show straight or concave.
  // Kept points there (at least root_cover_points, spanning at least
  // root_cover_share of the opening) that a parabola fits as a cap convex
  // towards the sensor (its curvature at least root_bump_t standard errors
  // from straight, given the profile's noise) and higher than the surface
  // tolerance in front of the root edges' line are something in the root
  // (a tack weld, a bead): the reading is rejected as `uncertain`.
  bool check_root_cover = true;
  // A bevel's points past the crossing of the bevels' lines that lie on its
  // own line and off the other's are kept (Matcher::trimmed): with a
  // mismatch and a root face, the lower bevel goes on below that crossing
  // to its root edge. false: trimmed, the root edge put where the crossing
  // left the bevel.
  bool keep_past_crossing = true;
  double root_cover_share = 0.5;
  int root_cover_points = 5;
  double root_bump_t = 4.0;
  // And of an open root's edges: a bevel ends where it is read. Its own
  // points past that edge towards the root (runs of at least 3 in
  // consecutive columns on its line and off the other bevel's, spanning
  // root_past_mm along it: the bevel going on beyond a dropout or a
  // shadow, not a surface crossing its line) lying more than root_past_mm
  // past it reject the reading as `uncertain`, as the butt's edges are
  // (ButtParams::edge_past_mm).
  bool check_root_past = true;
  double root_past_mm = 0.5;
  // An open root's edges lie as far apart across the plates as the plate
  // tops do (both seen). Where one stands higher than that (by more than
  // twice the edges' own rms across the plates), its bevel may go
  // on unseen down to the other's level (a shadow, a tack weld or a dropout
  // over its foot) unless a ray between the edges saw past that extension;
  // the stated error (TrackResult::track_sigma_mm) takes its edge as
  // anywhere on it (docs/JOINTS.md "Localization"). false: at its last
  // point only.
  bool unseen_root_extension = true;
  // And of its tops with beads laid (GrooveParams::vgroove_fill), as the
  // groove model's: more than
  // ConfidenceParams::unexplained_points (+ unexplained_share of those
  // looked at) points beyond a top's outer end, within window_mm of it,
  // standing more than the surface tolerance in front of that top's line
  // reject the reading: the "top" lies inside a wider groove (a fill's or a
  // bead's cap beside an unseen wall).
  bool check_tops_outside = true;
};

// The groove model (v-groove fill, single bevel, U, J; docs/JOINTS.md
// "Grooves and fill"): two plate tops, a wall below each top edge, and the
// groove's bottom between the walls (the root, or the last bead: the fill).
struct GrooveParams {
  double max_top_angle_deg = 10.0;  // the plate tops are parallel within this
  Range mismatch_mm{0.0, 5.0};      // plate b's top above or below a's, across the tops
  Range top_width_mm{2.0, 150.0};   // top edge to top edge
  Range depth_mm{0.5, 120.0};       // what is left to fill: the tops' line to the bottom's lowest point
  // A wall is a straight run of at least this many points below its top edge,
  // at least min_wall_deg to the plate top, starting within max_edge_mm of
  // the top's end (a chamfered or rounded top edge lies between). 3: the
  // fewest whose line has a residual to check; a wall the laser sees nearly
  // edge-on (a U's, a J's) often has no more.
  int min_wall_points = 3;
  double min_wall_deg = 20.0;
  double max_edge_mm = 3.0;
  // Of several such runs, the wall is the one reaching farthest from its
  // first point to its last: a rounded or chamfered top edge's piece is no
  // longer than its size, and a wall seen edge-on has few points spread
  // down the groove's depth (false: the run of most points, before
  // 2026-11-28, session 31; a bevel's square wall seen edge-on by 7 points
  // lost to its top edge's rounding, and the reading was rejected).
  bool wall_by_reach = true;
  // Each wall's angle to its plate top (90: square), per joint: a bevelled
  // wall (v-groove, a bevel's bevel, a J's straight part), a U's walls, and
  // a square wall (a bevel's and a J's other side; it may be hidden from the
  // camera, then it is taken as square).
  Range bevel_wall_deg{30.0, 82.0};
  Range u_wall_deg{65.0, 92.0};
  Range square_wall_deg{82.0, 95.0};
  // Narrower notches than this in the bottom (a root gap, the rays into it)
  // are closed at their shoulders: the groove's bottom is the root edges' level.
  double max_notch_mm = 4.0;
  // A U's or J's radius is no notch (U and J grooves): a notch whose inside
  // (6 points or more) is one circle, its points' rms within the surface
  // tolerance, that the bottom beside it on one side goes on along (the
  // shoulder and up to 3 points beyond it within 2 tolerances of the
  // circle) is kept as seen, unless the polyline's end there is the toe of
  // a wall not seen (placed from its top's edge) and off the circle. With
  // the plates' mismatch at a closed root, the lower plate's half of the
  // bottom is such a bowl (1-2 mm deep, 3-4 mm wide): closed at its
  // shoulders, B3 lay on the upper level, 1-2 mm from the root.
  bool radius_not_notch = true;
  // The bottom's steps (docs/JOINTS.md "Session 28"): where the polyline
  // joins two seen points (no closed notch) steeper than 2:1 whose levels,
  // each from up to 3 points, differ by more than
  // ConfidenceParams::track_interval_mm, and B3's place along the tops
  // (midway between the toes) lies within 3 of its standard deviations of
  // that piece, B3's depth is not known (a closed root with the plates'
  // mismatch: the line midway between the toes meets either level) and the
  // reading is rejected as uncertain. And B3 beside such a step rests on
  // the bottom, not on a reflection cluster, when its piece lies inside a
  // run of the polyline with no two neighbours farther apart than the
  // support check's offset (0.5 mm, or 3 surface tolerances if more), of
  // more points than a cluster and at least 1.5 mm long (along the tops).
  bool bottom_steps = true;
  // The v-groove is read by its own template and by this model. With
  // vgroove_fill (beads are laid in it: multi-pass welding; `vts track
  // --fill`) the model's reading stands unless the template's top edges and
  // track point lie within agree_mm of its own; without, the template's
  // (an empty groove: a bump in its root is a tack weld, not a bead).
  bool vgroove_fill = false;
  double agree_mm = 1.0;
  // The bottom is the root or the fill, below the tops: a straight run of it
  // at least plate_level_mm long (along the tops), parallel to them within
  // max_top_angle_deg and no deeper below their line than plate_level_share
  // of the groove's depth (or 2 surface tolerances) is a plate top going on
  // past a "wall" that is none (a dent, a dropout's or a reflection's edge),
  // and the reading is rejected.
  double plate_level_share = 0.2;
  double plate_level_mm = 3.0;
  // The track point is the bottom midway between the toes, the groove's
  // deepest part: B3 less than this share of the groove's depth below the
  // tops' line, on the way from one toe up to the other (deeper than one,
  // shallower than the other, within the surface tolerance), sits on a wall
  // read as the bottom, and the reading is rejected. A crest of the fill (B3
  // above both toes: a bead in the middle of a nearly full groove) is not.
  double min_track_depth_share = 0.5;
  // A wall below a top edge is joined with the segments after it on its
  // line: each point within the surface tolerance of the wall's line so far,
  // or (true) a segment of more points than a reflection cluster that is
  // one line with it (their joint fit within the tolerance and at most 1.5
  // times the rougher one's rms), also past more than two short pieces off
  // its line while these hold no more points than a reflection cluster. A
  // 10-point piece of a bevel wall cut off below its top edge by a
  // reflection cluster and two single points is 0.2 degrees off the
  // 131-point rest of it, which then lay up to 0.2 mm off its line: the
  // wall was read as the piece, and the 68 mm below as the groove's bottom.
  bool wall_joins_one_line = true;
};

// The profile's noise level and the tolerances that follow it (tracker/noise.h).
// Every tolerance below that noise must not cross is raised to a multiple of
// the noise sigma (across the surface, 1 sigma, mm) when that is larger than
// the tolerance's own value, so the same defaults serve ideal profiles and a
// real sensor's 0.2 mm RMS.
struct NoiseParams {
  // The sensor's noise, if known (> 0); 0: estimated from each profile
  // (estimate_noise_mm: median of second differences across the surface).
  double sigma_mm = 0.0;
  bool adapt = true;  // off: the tolerances are used as given
  double surface_k = 3.0;       // TrackerParams::surface_tol_mm
  double outlier_k = 5.0;       // OutlierParams::threshold_mm
  double support_k = 3.0;       // OutlierParams::support_tol_mm
  double split_k = 5.0;         // SegmentParams::split_threshold_mm
  double break_k = 6.0;         // SegmentParams::break_min_mm
  double merge_offset_k = 4.0;  // SegmentParams::max_merge_offset_mm
  double fit_k = 2.0;           // SegmentParams::fit_tol_mm
};

// How sure the tracker is of a reading, and when it says it is not
// (TrackResult::confidence, docs/JOINTS.md "Confidence").
//
// A reading's strength E is the log-likelihood ratio of "the joint as read"
// against "no joint here", over the points near its track point:
// - each point of its two plates, and each point between them, x sigmas off
//   the line that explains it (the nearer plate's), costs x^2 / 2 (the
//   Gaussian's negative log-likelihood, capped at cap_sigma^2 / 2 for
//   outliers); "no joint" explains them all with one of the two plates'
//   lines continued; sigma is TrackResult::noise_mm, or surface_tol_mm /
//   NoiseParams::surface_k when that is larger;
// - in an open joint (butt, v-groove), rays into it (invalid columns, points
//   behind both plates on a wall of the opening or deep enough) are one
//   event that "no joint" must explain as a random one, a dropout run or a
//   reflection cluster: ln(1 / p) with p the profile's rate of such events
//   per column (runs of invalid or removed columns between its first and
//   last usable one, leaving out the reading's own, (k + 1) / (n + 2)).
// The confidence is the reading's posterior probability among the distinct
// readings (rivals farther than distinct_mm) and "the joint is not in view",
// with the prior hidden_prior for the latter and the rest spread evenly over
// the profile's n usable points:
//   confidence = 1 / (1 + sum over rivals e^((E_r - E) / temperature) + (n hidden_prior + u) / (1 - hidden_prior) e^-E),
// u = 0 but for a butt with hidden_in_unseen (the columns its joint may lie
// under unread: the joint's place even over the n + u columns).
struct ConfidenceParams {
  double window_mm = 10.0;  // plate points this close to the track point are weighed
  // A point costs nothing within noise_k sigmas of the line that explains
  // it (noise and waviness are no evidence either way), then (x^2 - noise_k^2)
  // / 2 for x sigmas, up to x = cap_sigma (an outlier).
  double noise_k = 3.0;
  double cap_sigma = 5.0;
  double distinct_mm = 1.0;  // readings farther apart are different joints
  // The share of profiles in which the joint is not in view (a tack weld over
  // it, a shadow, the seam's ends): a lone weak reading is then noise.
  double hidden_prior = 0.05;
  // The confidence weighs a rival reading's (or a step's) log-likelihood
  // ratio to the reading divided by this temperature: each point and column
  // of the two readings' common window counts as independent, and the event
  // rates come from the profile's few events, so undivided the comparison
  // is overconfident (readings stated 0.95-0.99 sure were false reads one
  // time in five on the corpus' development seeds). 2 is the maximum-
  // likelihood temperature there (docs/JOINTS.md "Calibration"); 1 is the
  // raw posterior (as is any value not above 0). The "not in view" term and
  // TrackResult::strength are not divided.
  double temperature = 2.0;
  // true: the "not in view" term is divided by the temperature too, as the
  // rivals' are (docs/JOINTS.md "Calibration"): on 10,010 unseen corpus
  // profiles the butt's false reads more than 5 mm off (a dropout run
  // between coplanar plates read as a tight gap) fall from 86 to 41 for
  // 0.6 % of its right readings, but a clean tight gap (2-3 missing
  // columns, or a 1 mm gap at 200 mm showing 3 wall points) is then "weak"
  // read alone. false (default): undivided.
  bool temper_unseen = false;
  // true: a butt's "not in view" prior grows by the share of the profile's
  // columns where its joint may lie unread (a shadow's or dropout's run of
  // columns, wider than ButtParams::gap_mm's largest gap, between two kept
  // points, not the reading's own).
  bool hidden_in_unseen = true;
  // A run of invalid columns weighed as a random event may be one shadow
  // rather than a dropout run of the profile's own rate: its length k
  // columns costs the cheaper of (k - 1) ln(1 / q) (q the share of the
  // profile's other invalid columns that continue a run) and
  // ln(k (k + 1) / shadow_weight). 0: the run's rate alone.
  double shadow_weight = 0.05;
  // Readings less sure than this are rejected ("weak" or "ambiguous").
  double min_confidence = 0.9;
  // A reading must explain the points near the joint: it is rejected
  // ("unexplained") when more than unexplained_points plus unexplained_share
  // of the points in the window lie on none of its lines (a bead, a tack
  // weld, an obstacle: the joint may lie under it). Reflection clusters are
  // a few points.
  int unexplained_points = 6;
  double unexplained_share = 0.1;
  // Its plates must be lines there: rejected ("curved") when one's points
  // lie more than this many noise sigmas (rms) about its line.
  double max_plate_rms_sigma = 2.0;
  // Where the template works out how precisely its fits locate the track
  // point (TrackResult::track_sigma_mm; docs/JOINTS.md "Localization"), the
  // confidence is multiplied by the chance that the track point lies within
  // this distance (mm, a false read's) of where it is read; a reading left
  // below min_confidence mostly by it is rejected as "uncertain". 0: off.
  double track_interval_mm = 1.0;
  // A bump beyond the joint (a run of more points than a reflection cluster
  // standing in front of the reading's line on its side, that line's points
  // on both sides of it: a cap on the surface, a tack weld's or a bead's)
  // is a rival where the joint may lie, under it, as strong as its points'
  // cost under the reading (docs/JOINTS.md "Evidence"). false: not weighed.
  bool bump_rival = true;
  // A point beside the joint is weighed against the plate on its own side
  // only (or a line seen beside the plates), as a reading's cost counts it:
  // a surface there on the other plate's line says that plate goes on
  // (a tack weld's top read as a plate, the plate beyond it at the other
  // plate's level). false: the nearer of the two plates' lines (before
  // 2026-11-27).
  bool own_side_only = true;
};

// A prediction of where the joint is (sensor frame, mm), from the profiles
// before (tracker/follower.h): only readings within radius_mm of it count.
struct TrackPrior {
  Vec2 track_point = Vec2::Zero();
  double radius_mm = 5.0;
};

struct TrackerParams {
  JointType joint = JointType::Fillet;
  SegmentationParams segmentation;
  NoiseParams noise;
  ConfidenceParams confidence;
  FilletParams fillet;
  CornerParams corner;
  LapParams lap;
  ButtParams butt;
  VGrooveParams vgroove;
  GrooveParams groove;
  // How far a point may lie off a fitted surface and still count as on it,
  // and how far past a line a point must lie to count as beyond it (mm).
  // Ideal profiles need little; set it from the sensor's resolution.
  double surface_tol_mm = 0.02;
  // Largest distance between the two plates' facing end points that can still
  // be one joint (mm).
  double max_joint_width_mm = 20.0;
  // Plate edge faces (butt and lap edges, corner ends, v-groove root faces) are
  // square to the plate surface: a single point seen on such a face fixes the
  // edge exactly instead of only between two column rays.
  bool square_edges = true;
  // How far from square to its plate an edge face or wall that the camera
  // does not see may lie in the profile (rms, degrees): plates are cut
  // square to about a degree, and a sensor at lead angle p and side angle s
  // to the seam sees the section sheared by about sin p sin s radians (1.5
  // degrees at 15 and 6 degrees). Where such a face is drawn through a
  // plate's edge (a lap's with its edge face hidden, a groove's hidden
  // square wall), the point placed on it at a depth d below the edge is
  // known along the plate to no better than d times that angle
  // (docs/JOINTS.md "Localization"). 0: square exactly.
  double hidden_face_deg = 1.5;
  // Where a plate reaches over the points beside it that lie on its line
  // (butt plates, the fillet's web), it also reaches over single points off
  // it that lie in front of it or at most 2 surface_tol_mm behind it, between
  // two points on its line in the neighbouring columns (one noisy point; a
  // ray into a gap goes deeper).
  bool reach_over_single_points = true;
  // A butt plate's edge, and the lap's upper plate edge when its edge face is
  // hidden, are placed from the last of the points removed as outliers right
  // after the plate's end (no column missing or kept between) that lie on its
  // line (and off the lower plate's, for the lap), also past removed points
  // in front of it: a reflection cluster displaced towards the sensor next to
  // an edge is removed, and the few plate points between it and the edge are
  // then removed as an island; the plate's segment alone ended before them.
  bool reach_removed_points = true;
  // A plate's edge lies short of the first column beyond its end whose ray
  // shows that it missed the plate (tracker.cpp, edge_at): the columns right
  // beyond the end whose points were removed as outliers in front of both
  // plates (a reflection cluster over the edge; for a lap's upper plate with
  // its edge face hidden, any point in front of it or behind the lower
  // plate) are passed over, as their rays may have met the plate. false:
  // the next column.
  bool edge_past_reflections = true;
  // Step 4 detaches a segment's end points off its line only when they lie
  // farther than surface_tol_mm from it too (not only fit_tol_mm or 4 rms of
  // the fit): a surface seen nearly along the rays has its range noise along
  // its line, so its rms is far below the noise, and one point at a v-groove
  // bevel's root end 0.03 mm off (noise) detached the bevel's last points
  // there, moving its root edge millimetres.
  bool noise_aware_detach = true;
  // Step 2 also splits a region of at least min_segment_points whose line fit
  // has an rms above surface_tol_mm (no line with noise alone) at its
  // farthest point from the chord, when that lies more than surface_tol_mm
  // off and has at least 3 points on either side, each side fitting a line
  // with at most half the whole's rms (a corner, not a displaced cluster on
  // one line): a dropout next to a corner
  // leaves a short run in which the corner lies within split_threshold_mm of
  // the chord (a v-groove's bevel and root face at 50 mm, or its plate top
  // and bevel), and one segment across it moved the root edge or the top
  // line.
  bool split_rough_segments = true;
  // Step 1 keeps an island (a few points cut off on both sides) as a piece
  // of a surface when its points lie within surface_tol_mm of their chord
  // (not only OutlierParams::support_tol_mm) and the point beyond a cut
  // continues that line: on a far, noisy profile the few plate points
  // between a lap's step and a dropout are never straight to 0.1 mm, and
  // removed they moved the upper plate's edge by the run's width.
  bool noise_aware_islands = true;
};

}  // namespace vts::tracker
