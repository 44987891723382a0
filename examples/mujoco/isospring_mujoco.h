/* The isospring runtime inside MuJoCo: the terms of a calibrated model that MuJoCo has no
 * element for (volume, shear and strain-point terms) as passive forces.
 *
 * An MJCF scene exported by isospring (io/export_mjcf.hpp, `isospring export -o scene.xml`) has
 * the springs as tendons and names, in <custom><text name="isospring_model">, the model.json
 * next to it that carries the other terms. isospring_mujoco_attach loads that file with the
 * runtime, masks the springs out (MuJoCo's tendons run them) and maps every particle's slide
 * joints to the runtime's state; isospring_mujoco_passive, installed as mjcb_passive, then adds
 * the terms' forces to qfrc_passive at every step. MuJoCo's callbacks are global functions
 * without user data, so one scene at a time is attached (per process).
 */
#ifndef ISOSPRING_MUJOCO_H
#define ISOSPRING_MUJOCO_H

#include <mujoco/mujoco.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Loads the runtime model named by the scene `m` (read from `scene_path`, whose folder holds the
 * model.json) and installs the callback. Returns 1 when the scene has runtime terms and they are
 * attached, 0 when the scene has none (plain springs: nothing to do), -1 on an error written into
 * `error`. */
int isospring_mujoco_attach(const mjModel* m, const char* scene_path, char* error,
                            size_t error_size);

/* The passive-force callback (installed by attach). */
void isospring_mujoco_passive(const mjModel* m, mjData* d);

/* Removes the callback and frees the model. */
void isospring_mujoco_detach(void);

/* Particle displacements (particles * dimension of the runtime model) of the state in d; returns
 * the number of particles (0 when nothing is attached). */
size_t isospring_mujoco_displacements(const mjData* d, double* u, size_t size);

#ifdef __cplusplus
}
#endif

#endif /* ISOSPRING_MUJOCO_H */
