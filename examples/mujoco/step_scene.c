/* Loads a MuJoCo scene exported by isospring, attaches the isospring runtime for the terms MuJoCo
 * has no element for, and steps it:
 *
 *   isospring_mujoco_step SCENE.xml [STEPS] [PARTICLE FX FY FZ]...
 *
 * STEPS (default 1000) steps of the scene's time step under the scene's gravity and the given
 * constant forces [N] on particles; prints the runtime terms attached, the cost per step and the
 * largest particle displacement at the end. Exit code 1 on any error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "isospring_mujoco.h"

static double seconds(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char** argv) {
  if (argc < 2 || (argc > 3 && (argc - 3) % 4 != 0)) {
    fprintf(stderr, "usage: %s SCENE.xml [STEPS] [PARTICLE FX FY FZ]...\n", argv[0]);
    return 2;
  }
  char error[1000] = "";
  mjModel* m = mj_loadXML(argv[1], NULL, error, sizeof(error));
  if (!m) {
    fprintf(stderr, "%s: %s\n", argv[1], error);
    return 1;
  }
  mjData* d = mj_makeData(m);
  const int attached = isospring_mujoco_attach(m, argv[1], error, sizeof(error));
  if (attached < 0) {
    fprintf(stderr, "%s: %s\n", argv[1], error);
    mj_deleteData(d);
    mj_deleteModel(m);
    return 1;
  }
  printf("%s: %d bodies, %d tendons (springs); runtime terms %s\n", argv[1], m->nbody - 1,
         m->ntendon, attached ? "attached through mjcb_passive" : "none (plain springs)");
  const long steps = argc > 2 ? atol(argv[2]) : 1000;
  for (int k = 3; k + 3 < argc; k += 4) {
    char name[64];
    snprintf(name, sizeof(name), "particle_%s", argv[k]);
    const int body = mj_name2id(m, mjOBJ_BODY, name);
    if (body < 0) {
      fprintf(stderr, "%s: no free particle %s (fixed particles take no force)\n", argv[1],
              argv[k]);
      return 1;
    }
    for (int c = 0; c < 3; ++c) d->xfrc_applied[6 * body + c] = atof(argv[k + 1 + c]);
  }
  const double start = seconds();
  for (long s = 0; s < steps; ++s) mj_step(m, d);
  const double elapsed = seconds() - start;
  double largest = 0.0;
  for (int j = 0; j < m->njnt; ++j) largest = fmax(largest, fabs(d->qpos[m->jnt_qposadr[j]]));
  printf("%ld steps of %g s: %.1f us per step; largest displacement component %.6g m\n", steps,
         m->opt.timestep, steps > 0 ? 1e6 * elapsed / (double)steps : 0.0, largest);
  isospring_mujoco_detach();
  mj_deleteData(d);
  mj_deleteModel(m);
  return 0;
}
