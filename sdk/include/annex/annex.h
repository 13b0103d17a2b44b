#ifndef ANNEX_ANNEX_H
#define ANNEX_ANNEX_H
/// \file
/// The C API of Annex (libannex_c): a stable C ABI for engines and bindings (C#, Python,
/// Rust, ...), in the style of librealsense and the Azure Kinect SDK.
///
/// Conventions
/// - Objects are opaque handles made by `annex_*_create` / `annex_*_load_*` and freed by
///   the matching `annex_*_destroy` (which accepts NULL).
/// - Every call that can fail returns an `annex_status`; when `error` is not NULL it
///   receives NULL on success and, on failure, an `annex_error` the caller frees with
///   annex_error_destroy(). Its message reads "file:line:col: error: ..." when the failure
///   has a place in a file (spec, scene, PCD, config).
/// - Strings returned by the library are UTF-8 and owned by the handle they come from;
///   they stay valid until that handle is destroyed (session strings: until the next
///   annex_session_push()).
/// - Arrays are read with two calls: first with `capacity` 0 (the buffer may be NULL) to
///   learn `*count`, then with a buffer that holds it. A buffer too small gives
///   ANNEX_BUFFER_TOO_SMALL with `*count` set to the size needed.
/// - Bindings call annex_check_abi(ANNEX_ABI_VERSION, ...) first: the structs below are
///   laid out as this header says only for that ABI version.
///
/// Coordinates: the sensor frame of the depth camera, right-handed, metres: x right,
/// y down, z forward (out of the lens). Rotations are unit quaternions w, x, y, z that
/// turn model coordinates into sensor coordinates. annex_pose_to_unity() gives the same
/// pose in Unity's left-handed, y-up camera space.
///
/// Threading
/// - Different handles may be used from different threads at the same time.
/// - annex_spec, annex_frame, annex_scene and annex_match handles never change after
///   creation: any number of threads may read them (push one frame to several sessions,
///   create sessions, scans or matches from one spec) at once.
/// - An annex_session or annex_scanner must not be used by two threads at once: calls
///   on one session (push, objects, events, frame info) are made from one thread, or
///   the caller serialises them. The session runs its own worker threads, created by
///   annex_session_create() and joined by annex_session_destroy(); callbacks never run
///   on them (there are none).
/// - annex_version_string, annex_abi_version and annex_pose_to_unity may be called from
///   any thread at any time.

#include <stddef.h>
#include <stdint.h>

#include "annex/version.h"

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#if defined(ANNEX_C_BUILD)
#define ANNEX_API __declspec(dllexport)
#else
#define ANNEX_API __declspec(dllimport)
#endif
#else
#define ANNEX_API __attribute__((visibility("default")))
#endif

/// The layout of every struct in this header. Grows whenever one of them changes.
#define ANNEX_ABI_VERSION 1

typedef enum annex_status {
  ANNEX_OK = 0,
  ANNEX_INVALID_ARGUMENT = 1, /**< a NULL handle or buffer, a parameter out of range */
  ANNEX_PARSE_ERROR = 2,      /**< a spec, scene or config with an error at line:column */
  ANNEX_IO_ERROR = 3,         /**< a file that cannot be opened or read */
  ANNEX_SCAN_FAILED = 4,      /**< an empty frame, no support plane */
  ANNEX_BUFFER_TOO_SMALL = 5, /**< the array is larger than the capacity given */
  ANNEX_ABI_MISMATCH = 6,     /**< the caller was built for another ABI version */
  ANNEX_INTERNAL_ERROR = 7    /**< out of memory or a bug; the message says which */
} annex_status;

typedef struct annex_error annex_error;
typedef struct annex_spec annex_spec;
typedef struct annex_frame annex_frame;
typedef struct annex_scanner annex_scanner;
typedef struct annex_scene annex_scene;
typedef struct annex_match annex_match;
typedef struct annex_session annex_session;

/* ---- Errors and versions ---------------------------------------------------------- */

/// "origin:line:col: error: message" (or "error: message" without a place).
ANNEX_API const char* annex_error_message(const annex_error* error);
ANNEX_API annex_status annex_error_status(const annex_error* error);
/// The file (or "frame 12", "<text>") the error is in; "" when none.
ANNEX_API const char* annex_error_origin(const annex_error* error);
/// 1-based line and column; 0 when not applicable.
ANNEX_API int annex_error_line(const annex_error* error);
ANNEX_API int annex_error_column(const annex_error* error);
ANNEX_API void annex_error_destroy(annex_error* error);
/// A constant name for a status, e.g. "ANNEX_PARSE_ERROR".
ANNEX_API const char* annex_status_name(annex_status status);

/// The library's version, e.g. "0.1.0" (ANNEX_VERSION_STRING of the build).
ANNEX_API const char* annex_version_string(void);
/// The ABI version the library was built with (ANNEX_ABI_VERSION of its header).
ANNEX_API int annex_abi_version(void);
/// ANNEX_OK when `expected_abi` (pass ANNEX_ABI_VERSION) is the library's ABI version.
ANNEX_API annex_status annex_check_abi(int expected_abi, annex_error** error);

/* ---- Haptic specs ----------------------------------------------------------------- */

/// Reads and validates a `.haptic` file (docs/haptic-format.md).
ANNEX_API annex_status annex_spec_load_file(const char* path, annex_spec** out,
                                            annex_error** error);
/// Parses and validates spec text; `origin` (may be NULL: "<text>") names it in errors.
ANNEX_API annex_status annex_spec_load_text(const char* text, const char* origin,
                                            annex_spec** out, annex_error** error);
/// Only checks text: ANNEX_OK or the first error with its line and column.
ANNEX_API annex_status annex_spec_validate_text(const char* text, const char* origin,
                                                annex_error** error);
ANNEX_API void annex_spec_destroy(annex_spec* spec);
ANNEX_API size_t annex_spec_object_count(const annex_spec* spec);
/// The name of virtual object `index` (spec order); NULL when out of range.
ANNEX_API const char* annex_spec_object_name(const annex_spec* spec, size_t index);
/// Metres per unit of virtual object `index`'s mesh (the spec's `model_scale`, 1 when
/// the spec gives none); 0 when `index` is out of range. The pose of annex_object maps
/// the model's coordinates (metres); the mesh is drawn scaled by this first.
ANNEX_API double annex_spec_object_model_scale(const annex_spec* spec, size_t index);
/// Warnings that did not stop reading ("file:line:col: warning: ...").
ANNEX_API size_t annex_spec_warning_count(const annex_spec* spec);
ANNEX_API const char* annex_spec_warning(const annex_spec* spec, size_t index);

/* ---- Frames ----------------------------------------------------------------------- */

/// Pinhole intrinsics of the depth camera: u = fx x / z + cx, v = fy y / z + cy.
typedef struct annex_intrinsics {
  int width, height;
  double fx, fy, cx, cy;
} annex_intrinsics;

/// Kinect defaults: 640 x 480, f 525, centre 319.5, 239.5.
ANNEX_API void annex_intrinsics_init(annex_intrinsics* intrinsics);

/// An organized cloud: `xyz` holds width * height points of 3 floats, row-major, in the
/// sensor frame (metres), NaN where the sensor saw nothing. `rgb` (3 bytes a pixel) may
/// be NULL. The data are copied.
ANNEX_API annex_status annex_frame_from_points(const float* xyz, int width, int height,
                                               const uint8_t* rgb, annex_frame** out,
                                               annex_error** error);
/// A depth image: z = depth[v * width + u] * depth_scale_m metres (0.001 for millimetres),
/// back-projected through `intrinsics` (whose size must match); 0 means no reading.
/// `rgb` (registered to the depth image, same size) may be NULL.
ANNEX_API annex_status annex_frame_from_depth(const uint16_t* depth, int width, int height,
                                              const annex_intrinsics* intrinsics,
                                              double depth_scale_m, const uint8_t* rgb,
                                              annex_frame** out, annex_error** error);
/// Reads a `.pcd` file (ascii, binary or binary_compressed).
ANNEX_API annex_status annex_frame_load_pcd(const char* path, annex_frame** out,
                                            annex_error** error);
ANNEX_API void annex_frame_destroy(annex_frame* frame);
ANNEX_API int annex_frame_width(const annex_frame* frame);
ANNEX_API int annex_frame_height(const annex_frame* frame);
/// Two-call copy of the points as x, y, z floats: `*count` is the number of floats.
ANNEX_API annex_status annex_frame_points(const annex_frame* frame, float* xyz,
                                          size_t capacity, size_t* count, annex_error** error);

/* ---- Scanning --------------------------------------------------------------------- */

/// The scan parameters most setups change (every other one keeps the scanner's
/// default; annex_scanner_create_from_config reads them all from a scan.conf file).
typedef struct annex_scan_params {
  double camera_tilt_deg;      /**< the camera looks down by this much (up = -y turned) */
  double max_plane_angle_deg;  /**< supports tilt at most this far from up */
  double min_height_m;         /**< objects stand between these heights above the support */
  double max_height_m;
  double max_depth_m;          /**< farther points are ignored */
  double cluster_tolerance_m;  /**< neighbours closer than this join one object */
  int min_cluster_points;      /**< smaller clusters are dropped */
  int threads;                 /**< threads of one scan (a background session scans on one) */
} annex_scan_params;

ANNEX_API void annex_scan_params_init(annex_scan_params* params);

/// Checks the parameters (a negative size is ANNEX_INVALID_ARGUMENT naming the field).
/// `params` may be NULL for the defaults.
ANNEX_API annex_status annex_scanner_create(const annex_scan_params* params,
                                            annex_scanner** out, annex_error** error);
/// Every parameter from a scan config file (`key value` lines, samples/config/scan.conf).
ANNEX_API annex_status annex_scanner_create_from_config(const char* path, annex_scanner** out,
                                                        annex_error** error);
ANNEX_API void annex_scanner_destroy(annex_scanner* scanner);
/// Finds the support plane and the physical objects on it, and the flat surfaces a
/// virtual panel may lie on (annex_scene_surface_count, annex_scene_with_surfaces).
/// ANNEX_SCAN_FAILED when the frame is empty or holds no support.
ANNEX_API annex_status annex_scan(annex_scanner* scanner, const annex_frame* frame,
                                  annex_scene** out, annex_error** error);

/* ---- Physical scenes -------------------------------------------------------------- */

typedef enum annex_shape {
  ANNEX_SHAPE_SPHERE = 0,
  ANNEX_SHAPE_CYLINDER = 1,
  ANNEX_SHAPE_CONE = 2,
  ANNEX_SHAPE_TORUS = 3,
  ANNEX_SHAPE_BOX = 4,
  ANNEX_SHAPE_PLANE = 5 /**< a flat rectangle (size_x, size_y); axis its normal */
} annex_shape;

/// A primitive fitted to a physical object, in the sensor frame.
typedef struct annex_primitive {
  annex_shape shape;
  const char* shape_name;         /**< "sphere", "cylinder", ... */
  int dimension_count;            /**< entries used in the two arrays below */
  const char* dimension_names[3]; /**< "radius", "height", "size_x", ... */
  double dimensions_m[3];
  double center[3];
  double axis[3]; /**< symmetry axis (box: its local z) */
  double fit;     /**< share of the object's points the shape explains, [0, 1] */
} annex_primitive;

typedef struct annex_physical_object {
  const char* id;      /**< "p1", "p2", ... left to right */
  int primitive_count; /**< the salient one first; 0 when the shape is unknown */
  int point_count;
  double fit; /**< quality of the salient fit, [0, 1] */
} annex_physical_object;

/// Reads a `.scene` file (docs/scene-format.md).
ANNEX_API annex_status annex_scene_load_file(const char* path, annex_scene** out,
                                             annex_error** error);
ANNEX_API void annex_scene_destroy(annex_scene* scene);
ANNEX_API size_t annex_scene_object_count(const annex_scene* scene);
ANNEX_API annex_status annex_scene_object(const annex_scene* scene, size_t index,
                                          annex_physical_object* out, annex_error** error);
ANNEX_API annex_status annex_scene_primitive(const annex_scene* scene, size_t object,
                                             size_t primitive, annex_primitive* out,
                                             annex_error** error);
/// The id of the object that object `index` stands on (a box on a box, a jar on a tin);
/// "" when it stands on the support itself, NULL when `index` is out of range.
ANNEX_API const char* annex_scene_object_on(const annex_scene* scene, size_t index);
/// The flat surfaces a scan found for virtual panels (docs/perception.md, "Flat surfaces
/// for virtual panels"): a support's free rectangle `s1.free`, a box's top `p3.top`, a
/// slab's broad face `p1.face`. They are not among the scene's objects (so they never
/// change the objects' indices or votes); 0 for a scene read from a file.
ANNEX_API size_t annex_scene_surface_count(const annex_scene* scene);
/// A new scene (free it with annex_scene_destroy) whose objects are `scene`'s objects
/// followed by its surfaces: objects annex_scene_object_count(scene) and on are the
/// surfaces, each with one ANNEX_SHAPE_PLANE primitive (size_x >= size_y, axis its
/// normal pointing up, center the rectangle's centre). Match a spec with plane
/// primitives against it to annex panels; its own surface count is 0.
ANNEX_API annex_status annex_scene_with_surfaces(const annex_scene* scene, annex_scene** out,
                                                 annex_error** error);
/// The direction of a plane primitive's size_x side (a unit vector in its plane): 1 when
/// the primitive is a plane that has one, else 0 (other shapes, out of range).
ANNEX_API int annex_scene_primitive_x_axis(const annex_scene* scene, size_t object,
                                           size_t primitive, double x_axis[3]);
/// The support plane n . x + d = 0 (n up, away from it): 1 when the scene has one, else 0.
ANNEX_API int annex_scene_support(const annex_scene* scene, double normal[3], double* d);

/* ---- Matching --------------------------------------------------------------------- */

typedef struct annex_match_entry {
  const char* virtual_name;
  const char* physical_id; /**< NULL: virtual-only (no prop) */
  double vote;
} annex_match_entry;

/// The ObjectFinder: every annexable virtual object votes for every physical object, the
/// Hungarian method assigns them (docs/voting.md).
ANNEX_API annex_status annex_match_objects(const annex_spec* spec, const annex_scene* scene,
                                           annex_match** out, annex_error** error);
ANNEX_API void annex_match_destroy(annex_match* match);
/// One entry per virtual object, spec order.
ANNEX_API size_t annex_match_count(const annex_match* match);
ANNEX_API annex_status annex_match_entry_at(const annex_match* match, size_t index,
                                            annex_match_entry* out, annex_error** error);
/// Why virtual object `virtual_index` voted what it did for physical object
/// `physical_index`: the primitives paired, each dimension's ratio and weight. NULL when
/// that virtual object did not vote (not annexable) or an index is out of range.
ANNEX_API const char* annex_match_explanation(const annex_match* match, size_t virtual_index,
                                              size_t physical_index);
/// The whole vote table with every pair's breakdown, as `annex-runtime match --explain`.
ANNEX_API const char* annex_match_report(const annex_match* match);

/* ---- Sessions --------------------------------------------------------------------- */

typedef struct annex_session_params {
  annex_scan_params scan;
  int scan_every;           /**< frames between scans once something is annexed */
  int release_after_frames; /**< a prop lost this long is released */
  int threads;              /**< tracker threads (created once, with the session) */
  double min_vote;          /**< pairs voting at or below this are never matched */
  /// 1 (default): a scan runs on the session's scan worker beside tracking and applies
  /// at the first push after it finished, so no push waits for a scan. 0: a push that
  /// scans waits for it and shows its matches at once (offline processing, tests).
  int background_scan;
  int has_intrinsics; /**< 1: use `intrinsics`; 0: estimate them from the first frame */
  annex_intrinsics intrinsics;
} annex_session_params;

ANNEX_API void annex_session_params_init(annex_session_params* params);

/// The spec is copied: it may be destroyed afterwards. `params` may be NULL (defaults);
/// they are checked here (ANNEX_INVALID_ARGUMENT naming the field).
ANNEX_API annex_status annex_session_create(const annex_spec* spec,
                                            const annex_session_params* params,
                                            annex_session** out, annex_error** error);
/// As annex_session_create, but every scan parameter from a scan config file
/// (samples/config/scan.conf: the camera's noise model `depth_noise`, the supports, every
/// threshold) in place of `params->scan`, whose `threads` alone still applies. A missing
/// file is ANNEX_IO_ERROR, a bad line ANNEX_PARSE_ERROR naming file:line:column.
ANNEX_API annex_status annex_session_create_with_scan_config(const annex_spec* spec,
                                                             const annex_session_params* params,
                                                             const char* scan_config_path,
                                                             annex_session** out,
                                                             annex_error** error);
ANNEX_API void annex_session_destroy(annex_session* session);

/// One frame: track every annexed prop, start or apply scans, vote and match. A scan
/// that fails (no support in view) is not an error of the push: see annex_frame_info.
ANNEX_API annex_status annex_session_push(annex_session* session, const annex_frame* frame,
                                          annex_error** error);

typedef enum annex_tracking_state {
  ANNEX_STATE_TRACKING = 0, /**< ICP followed the prop this frame */
  ANNEX_STATE_HELD = 1,     /**< ICP failed, the last pose is kept */
  ANNEX_STATE_REINIT = 2,   /**< found again by the InitialAligner this frame */
  ANNEX_STATE_LOST = 3      /**< not found; released after release_after_frames */
} annex_tracking_state;

/// A virtual object annexed to a prop, as the last push left it. The pose is the virtual
/// model's: model coordinates to sensor coordinates, scaled along the model's axes by
/// `scale` first, then rotated by `rotation`, then moved by `position`.
typedef struct annex_object {
  const char* virtual_name;
  const char* physical_id; /**< stable while the prop stays annexed */
  int virtual_index;       /**< spec order */
  annex_tracking_state state;
  double confidence; /**< [0, 1], the tracker's last fitness, decaying while held or lost */
  double vote;       /**< the vote the match was made with */
  double position[3];
  double rotation[4]; /**< w, x, y, z */
  double scale[3];
  int matched_frame; /**< the push (0-based) that annexed it */
} annex_object;

ANNEX_API annex_status annex_session_objects(const annex_session* session, annex_object* out,
                                             size_t capacity, size_t* count,
                                             annex_error** error);

typedef enum annex_event_kind {
  ANNEX_EVENT_ANNEXED = 0,  /**< a virtual object got a prop */
  ANNEX_EVENT_LOST = 1,     /**< its prop went out of sight (state became lost) */
  ANNEX_EVENT_RELEASED = 2  /**< lost too long: the prop is given up, the object votes again */
} annex_event_kind;

typedef struct annex_event {
  annex_event_kind kind;
  const char* virtual_name;
  const char* physical_id;
  int frame; /**< the push (0-based) it happened in */
} annex_event;

/// The events of the last push.
ANNEX_API annex_status annex_session_events(const annex_session* session, annex_event* out,
                                            size_t capacity, size_t* count,
                                            annex_error** error);

typedef struct annex_frame_info {
  int frame;             /**< pushes so far minus one */
  int scan_applied;      /**< 1 when a scan's result applied in this push */
  int scan_frame;        /**< the push that scan was taken from; -1 when none applied */
  int scan_failed;       /**< 1 when that scan found no support (see scan_error) */
  const char* scan_error; /**< its message, or NULL */
  int matched;           /**< 1 when a match ran (some virtual object voted) */
  double scan_ms;        /**< the applied scan's time (on the scan worker when background) */
  double track_ms;       /**< all trackers, wall clock */
  double total_ms;       /**< the push */
} annex_frame_info;

ANNEX_API annex_status annex_session_frame_info(const annex_session* session,
                                                annex_frame_info* out, annex_error** error);

/* ---- Unity ------------------------------------------------------------------------ */

/// The same pose in Unity's left-handed, y-up camera space (x right, y up, z forward):
/// the sensor frame mirrored in y. position (x, y, z) -> (x, -y, z); rotation w, x, y, z
/// -> Unity's Quaternion(x, y, z, w) = (-x, y, -z, w), i.e. the rotation S R S with
/// S = diag(1, -1, 1). The model's own coordinates are taken mirrored the same way, so
/// the per-axis scale is unchanged. Either output pointer may alias its input.
ANNEX_API void annex_pose_to_unity(const double position[3], const double rotation_wxyz[4],
                                   double unity_position[3], double unity_rotation_xyzw[4]);

#ifdef __cplusplus
}  // extern "C"
#endif

#endif  // ANNEX_ANNEX_H
