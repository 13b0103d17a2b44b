/* Annex from C: load a spec, push the frames of a recording (a directory of .pcd files
 * named on the command line) through a session as a render loop would, and print each
 * annexed object's pose in the sensor frame and in Unity's convention, and the events.
 *
 *   annex_example_c SPEC.haptic FRAME.pcd...
 */
#include <stdio.h>
#include <stdlib.h>

#include "annex/annex.h"

/* Prints the error, frees it and tells the caller to stop. */
static int failed(annex_status status, annex_error* error) {
  if (status == ANNEX_OK) return 0;
  fprintf(stderr, "annex_example_c: %s (%s)\n", error ? annex_error_message(error) : "?",
          annex_status_name(status));
  annex_error_destroy(error);
  return 1;
}

static const char* event_name(annex_event_kind kind) {
  switch (kind) {
    case ANNEX_EVENT_ANNEXED: return "annexed";
    case ANNEX_EVENT_LOST: return "lost";
    case ANNEX_EVENT_RELEASED: return "released";
  }
  return "?";
}

int main(int argc, char** argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: %s SPEC.haptic FRAME.pcd...\n", argv[0]);
    return 2;
  }
  annex_error* error = NULL;
  /* Bindings check the ABI first: the structs below are laid out for this version. */
  if (failed(annex_check_abi(ANNEX_ABI_VERSION, &error), error)) return 1;
  printf("annex %s (C ABI %d)\n", annex_version_string(), annex_abi_version());

  annex_spec* spec = NULL;
  if (failed(annex_spec_load_file(argv[1], &spec, &error), error)) return 1;

  annex_session_params params;
  annex_session_params_init(&params);
  /* Frames read from files are processed offline: a push that scans waits for it, so the
     output does not depend on the machine's speed. A render loop keeps the default
     background scans (no push waits for a scan; docs/embedding.md). */
  params.background_scan = 0;
  annex_session* session = NULL;
  if (failed(annex_session_create(spec, &params, &session, &error), error)) return 1;
  annex_spec_destroy(spec); /* the session keeps its own copy */

  annex_object* objects = NULL;
  size_t capacity = 0;
  int status = 0;
  for (int i = 2; i < argc && status == 0; ++i) {
    annex_frame* frame = NULL;
    if (failed(annex_frame_load_pcd(argv[i], &frame, &error), error)) {
      status = 1;
      break;
    }
    annex_status s = annex_session_push(session, frame, &error);
    annex_frame_destroy(frame);
    if (failed(s, error)) {
      status = 1;
      break;
    }

    annex_event events[16];
    size_t event_count = 0;
    if (failed(annex_session_events(session, events, 16, &event_count, &error), error)) {
      status = 1;
      break;
    }
    for (size_t e = 0; e < event_count; ++e)
      printf("frame %d %s %s %s\n", events[e].frame, event_name(events[e].kind),
             events[e].virtual_name, events[e].physical_id);

    /* Two calls: the count, then the objects into a buffer that holds them. */
    size_t count = 0;
    if (failed(annex_session_objects(session, NULL, 0, &count, &error), error)) {
      status = 1;
      break;
    }
    if (count > capacity) {
      annex_object* grown = realloc(objects, count * sizeof *objects);
      if (!grown) {
        status = 1;
        break;
      }
      objects = grown;
      capacity = count;
    }
    if (failed(annex_session_objects(session, objects, capacity, &count, &error), error)) {
      status = 1;
      break;
    }
    for (size_t k = 0; k < count; ++k) {
      const annex_object* o = &objects[k];
      double up[3], uq[4];
      annex_pose_to_unity(o->position, o->rotation, up, uq);
      printf("frame %d %s on %s state=%d t=%.4f,%.4f,%.4f unity=%.4f,%.4f,%.4f scale=%.3f,%.3f,%.3f\n",
             i - 2, o->virtual_name, o->physical_id, (int)o->state, o->position[0], o->position[1],
             o->position[2], up[0], up[1], up[2], o->scale[0], o->scale[1], o->scale[2]);
    }
  }
  free(objects);
  annex_session_destroy(session);
  return status;
}
