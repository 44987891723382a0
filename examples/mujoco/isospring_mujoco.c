/* The isospring runtime as MuJoCo's passive-force callback (isospring_mujoco.h). */
#include "isospring_mujoco.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "isospring/runtime/runtime.h"

/* The attached scene: the runtime model, the qpos/qvel address of every particle component (-1
 * for a fixed particle's, which stays at rest) and the state and force arrays of one step,
 * allocated at attach so that a step allocates nothing. */
static struct {
  isospring_model* model;
  size_t size; /* particles * dimension */
  int* qpos;   /* per component: qpos address, or -1 */
  int* dof;    /* per component: dof (qvel, qfrc) address, or -1 */
  double* x;
  double* v;
  double* f;
} attached;

static void set_error(char* error, size_t size, const char* message, const char* detail) {
  if (error && size > 0) snprintf(error, size, "%s%s", message, detail ? detail : "");
}

/* The model.json path: the custom text's value, relative to the scene's folder. */
static int model_path(const mjModel* m, const char* scene_path, char* path, size_t size) {
  const int id = mj_name2id(m, mjOBJ_TEXT, "isospring_model");
  if (id < 0) return 0;
  const char* name = m->text_data + m->text_adr[id];
  const char* slash = scene_path ? strrchr(scene_path, '/') : NULL;
  if (name[0] == '/' || !slash)
    snprintf(path, size, "%s", name);
  else
    snprintf(path, size, "%.*s/%s", (int)(slash - scene_path), scene_path, name);
  return 1;
}

/* Joint "particle_<p>_<x|y|z>" of every free particle component. */
static int map_joints(const mjModel* m, char* error, size_t error_size) {
  const int dim = isospring_model_dimension(attached.model);
  const size_t particles = isospring_model_particle_count(attached.model);
  for (size_t p = 0; p < particles; ++p)
    for (int c = 0; c < dim; ++c) {
      const size_t e = p * (size_t)dim + (size_t)c;
      attached.qpos[e] = attached.dof[e] = -1;
      if (isospring_model_particle_fixed(attached.model, p)) continue;
      char name[64];
      snprintf(name, sizeof(name), "particle_%zu_%c", p, "xyz"[c]);
      const int joint = mj_name2id(m, mjOBJ_JOINT, name);
      if (joint < 0) {
        set_error(error, error_size, "the scene has no slide joint ", name);
        return 0;
      }
      attached.qpos[e] = m->jnt_qposadr[joint];
      attached.dof[e] = m->jnt_dofadr[joint];
    }
  return 1;
}

int isospring_mujoco_attach(const mjModel* m, const char* scene_path, char* error,
                            size_t error_size) {
  isospring_mujoco_detach();
  char path[4096];
  if (!model_path(m, scene_path, path, sizeof(path))) return 0;
  attached.model = isospring_model_load(path, error, error_size);
  if (!attached.model) return -1;
  /* MuJoCo's tendons are the springs; the runtime adds everything else. */
  isospring_model_set_terms(attached.model, ISOSPRING_TERM_ALL & ~ISOSPRING_TERM_SPRINGS);
  attached.size = isospring_model_state_size(attached.model);
  attached.qpos = malloc(attached.size * sizeof(int));
  attached.dof = malloc(attached.size * sizeof(int));
  attached.x = malloc(attached.size * sizeof(double));
  attached.v = malloc(attached.size * sizeof(double));
  attached.f = malloc(attached.size * sizeof(double));
  if (!attached.qpos || !attached.dof || !attached.x || !attached.v || !attached.f) {
    set_error(error, error_size, "out of memory attaching ", path);
    isospring_mujoco_detach();
    return -1;
  }
  if (!map_joints(m, error, error_size)) {
    isospring_mujoco_detach();
    return -1;
  }
  mjcb_passive = isospring_mujoco_passive;
  return 1;
}

void isospring_mujoco_passive(const mjModel* m, mjData* d) {
  (void)m;
  if (!attached.model) return;
  const double* rest = isospring_model_rest_positions(attached.model);
  for (size_t e = 0; e < attached.size; ++e) {
    const int q = attached.qpos[e];
    attached.x[e] = rest[e] + (q >= 0 ? d->qpos[q] : 0.0);
    attached.v[e] = q >= 0 ? d->qvel[attached.dof[e]] : 0.0;
  }
  isospring_model_forces(attached.model, attached.x, attached.v, attached.f);
  for (size_t e = 0; e < attached.size; ++e)
    if (attached.dof[e] >= 0) d->qfrc_passive[attached.dof[e]] += attached.f[e];
}

size_t isospring_mujoco_displacements(const mjData* d, double* u, size_t size) {
  if (!attached.model || size < attached.size) return 0;
  for (size_t e = 0; e < attached.size; ++e)
    u[e] = attached.qpos[e] >= 0 ? d->qpos[attached.qpos[e]] : 0.0;
  return isospring_model_particle_count(attached.model);
}

void isospring_mujoco_detach(void) {
  if (mjcb_passive == isospring_mujoco_passive) mjcb_passive = NULL;
  isospring_model_free(attached.model);
  free(attached.qpos);
  free(attached.dof);
  free(attached.x);
  free(attached.v);
  free(attached.f);
  memset(&attached, 0, sizeof(attached));
}
