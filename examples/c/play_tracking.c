/* Plays a recorded tracking sequence through a Deixis translator, with the C API.
 *
 *   play_tracking_c TRACKING.csv TARGET_MAP.json
 *
 * TRACKING.csv is in the column layout of `deixis capture csv` (docs/dataset.md; extra columns
 * are ignored), TARGET_MAP.json this room's objects (docs/target-map.md). The person is
 * calibrated on the first frame (they stand upright there); their avatar stands at (0.3, 0, -1.0)
 * facing -Z, wearing the shipped default avatar and driven by the shipped MoE networks. Prints,
 * per tick: the tick, whether the avatar is visible and holding its last frame, and its deictic
 * index fingertip after IK (metres, this room's world frame). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "deixis/deixis.h"

#define MAX_COLUMNS 256
#define MAX_LINE 8192

/* The columns of the capture's CSV this program reads, by name. */
static const char* const kColumns[] = {"time",
                                       "valid",
                                       "head_x",
                                       "head_y",
                                       "head_z",
                                       "head_q_x",
                                       "head_q_y",
                                       "head_q_z",
                                       "head_q_w",
                                       "gaze_x",
                                       "gaze_y",
                                       "gaze_z",
                                       "left_wrist_x",
                                       "left_wrist_y",
                                       "left_wrist_z",
                                       "left_wrist_q_x",
                                       "left_wrist_q_y",
                                       "left_wrist_q_z",
                                       "left_wrist_q_w",
                                       "left_tip_x",
                                       "left_tip_y",
                                       "left_tip_z",
                                       "right_wrist_x",
                                       "right_wrist_y",
                                       "right_wrist_z",
                                       "right_wrist_q_x",
                                       "right_wrist_q_y",
                                       "right_wrist_q_z",
                                       "right_wrist_q_w",
                                       "right_tip_x",
                                       "right_tip_y",
                                       "right_tip_z",
                                       "head_target",
                                       "hand_target",
                                       "head_target_x",
                                       "head_target_y",
                                       "head_target_z",
                                       "hand_target_x",
                                       "hand_target_y",
                                       "hand_target_z"};
enum { kColumnCount = sizeof kColumns / sizeof kColumns[0] };

/* Splits a CSV line in place; returns the number of fields. */
static int split(char* line, char** fields) {
  line[strcspn(line, "\r\n")] = '\0';
  int n = 0;
  char* p = line;
  while (n < MAX_COLUMNS) {
    fields[n++] = p;
    p = strchr(p, ',');
    if (p == NULL) {
      break;
    }
    *p++ = '\0';
  }
  return n;
}

static int column_of(char** header, int count, const char* name) {
  for (int i = 0; i < count; ++i) {
    if (strcmp(header[i], name) == 0) {
      return i;
    }
  }
  return -1;
}

static deixis_vec3 vec3(const double* v) {
  deixis_vec3 r = {(float)v[0], (float)v[1], (float)v[2]};
  return r;
}

static deixis_quat quat(const double* v) {
  deixis_quat q = {(float)v[0], (float)v[1], (float)v[2], (float)v[3]};
  return q;
}

/* One row's values, in kColumns' order, as a tracking frame. */
static deixis_tracking_frame frame_from(const double* v) {
  deixis_tracking_frame f;
  deixis_tracking_frame_init(&f);
  f.time = v[0];
  f.valid = (uint32_t)v[1];
  f.head.position = vec3(v + 2);
  f.head.orientation = quat(v + 5);
  f.gaze = vec3(v + 9);
  for (int h = 0; h < 2; ++h) {
    const double* w = v + 12 + 10 * h;
    f.wrist[h].position = vec3(w);
    f.wrist[h].orientation = quat(w + 3);
    f.index_tip[h] = vec3(w + 7);
  }
  f.head_target = (int32_t)v[32];
  f.hand_target = (int32_t)v[33];
  f.head_target_position = vec3(v + 34);
  f.hand_target_position = vec3(v + 37);
  return f;
}

static int fail(const char* what, const char* message) {
  fprintf(stderr, "play_tracking_c: %s: %s\n", what, message);
  return 1;
}

int main(int argc, char** argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: %s TRACKING.csv TARGET_MAP.json\n", argv[0]);
    return 2;
  }
  FILE* csv = fopen(argv[1], "r");
  if (csv == NULL) {
    return fail(argv[1], "cannot open");
  }
  static char line[MAX_LINE];
  char* fields[MAX_COLUMNS];
  if (fgets(line, sizeof line, csv) == NULL) {
    fclose(csv);
    return fail(argv[1], "empty");
  }
  int columns[kColumnCount];
  const int header_count = split(line, fields);
  for (int c = 0; c < kColumnCount; ++c) {
    columns[c] = column_of(fields, header_count, kColumns[c]);
    if (columns[c] < 0) {
      fclose(csv);
      return fail(argv[1], kColumns[c]);
    }
  }

  deixis_error error;
  deixis_mpnet* mpnet = NULL;
  deixis_ugnet* ugnet = NULL;
  deixis_avatar* avatar = NULL;
  deixis_room* room = NULL;
  deixis_translator* translator = NULL;
  int status = 1;
  if (deixis_mpnet_load(DEIXIS_ABI_VERSION, NULL, &mpnet, &error) != DEIXIS_OK ||
      deixis_ugnet_load(DEIXIS_ABI_VERSION, NULL, &ugnet, &error) != DEIXIS_OK ||
      deixis_avatar_load(DEIXIS_ABI_VERSION, NULL, &avatar, &error) != DEIXIS_OK ||
      deixis_room_create(DEIXIS_ABI_VERSION, argv[2], &room, &error) != DEIXIS_OK) {
    fail("loading", error.message);
    goto done;
  }

  char data_dir[4096];
  size_t data_dir_length = 0;
  if (deixis_data_dir(data_dir, sizeof data_dir, &data_dir_length) == DEIXIS_OK) {
    fprintf(stderr, "play_tracking_c: weights and avatar from %s\n", data_dir);
  }

  long tick = 0;
  while (fgets(line, sizeof line, csv) != NULL) {
    const int count = split(line, fields);
    double v[kColumnCount];
    for (int c = 0; c < kColumnCount; ++c) {
      v[c] = columns[c] < count ? strtod(fields[columns[c]], NULL) : NAN;
    }
    const deixis_tracking_frame frame = frame_from(v);
    if (translator == NULL) {
      deixis_upright_body body;
      deixis_upright_body_init(&body);
      deixis_translator_config config;
      deixis_translator_config_init(&config);
      if (deixis_calibrate_upright(&frame, &body, &config.person, &error) != DEIXIS_OK) {
        fail("calibrating on the first frame", error.message);
        goto done;
      }
      config.avatar_floor.position.x = 0.3f;
      config.avatar_floor.position.z = -1.0f;
      if (deixis_translator_create(DEIXIS_ABI_VERSION, mpnet, ugnet, avatar, &config, &translator,
                                   &error) != DEIXIS_OK) {
        fail("creating the translator", error.message);
        goto done;
      }
    }
    deixis_avatar_frame out;
    if (deixis_translator_tick(translator, &frame, room, &out) != DEIXIS_OK) {
      fail("tick", deixis_translator_last_error(translator));
      goto done;
    }
    printf("%ld %d %d %.5f %.5f %.5f\n", tick++, out.visible, out.held, out.fingertip.x,
           out.fingertip.y, out.fingertip.z);
  }
  status = 0;

done:
  deixis_translator_destroy(translator);
  deixis_room_destroy(room);
  deixis_avatar_destroy(avatar);
  deixis_ugnet_destroy(ugnet);
  deixis_mpnet_destroy(mpnet);
  fclose(csv);
  return status;
}
