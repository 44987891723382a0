/* isospring runtime: a calibrated spring model inside an engine's step loop.
 *
 * A plain C API (usable from C, C++ and, through the Python module, Python) that loads the
 * model.json written by `isospring calibrate` (schema "isospring-spring-model", version 1,
 * docs/outputs.md) or a reduced model written by `isospring export --format reduced`
 * ("isospring.reduced_spring_model", docs/reduced_model.md) and evaluates, for EVERY term the
 * calibration produces, the forces and their Jacobian-vector products:
 *
 *   springs          E = 1/2 k (|x_i - x_j| - L0)^2, damping -c (l . dl/dt) l / |l|^2
 *   cell volume      E = 1/2 (kappa / |V0|) (V(x) - V0)^2, V the trilinear (2D: bilinear) cell
 *   cell shear       E = mu |V0| |dev G|^2 of the cell's mean Green strain
 *   point volume     E = 1/2 kappa |V0| (det F - 1)^2, F = sum_a x_a (dR_a/dX)^T
 *   point shear      E = mu |V0| |dev G|^2, G = 1/2 (F^T F - I)
 *   reduced model    E = 1/2 q^T Lambda q, damping -C_r qdot (in the model's own coordinates q)
 *   corotated        the network's rest stiffness and damping in each particle's shape-matched
 *   reduced model    frame, projected: g = Phi^T f_corot(X + Phi q, Phi qdot), exactly zero for
 *                    rigid motions; E = 1/2 sum_i l_i . sum_j K_ij l_j (l: displacements in
 *                    particle i's frame; f is not exactly its gradient); the Jacobian-vector
 *                    product is taken at frozen rotations. A reduced file with a "corotation"
 *                    object (`isospring export --format reduced --corotated`); O(n r) per call.
 *
 * (definitions: analysis/spring_network.hpp, spring_volume.hpp, spring_strain_point.hpp,
 * spring_reduced_model.hpp). Everything is allocated by the load; no call after it allocates.
 *
 * State vectors are flat arrays of isospring_model_state_size() doubles: for a network, particle
 * q's component c at q * dimension + c (absolute positions x, velocities v); for a reduced model
 * the reduced coordinates q and their rates. Evaluation functions read the model only, so one
 * loaded model may be evaluated from several threads at once (except a corotated reduced model,
 * whose evaluations use its scratch); isospring_model_set_terms and
 * isospring_model_reduced_step change the model (its scratch), so they must not run concurrently
 * with anything else on the same model.
 */
#ifndef ISOSPRING_RUNTIME_RUNTIME_H
#define ISOSPRING_RUNTIME_RUNTIME_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct isospring_model isospring_model;

/* What a file holds. */
enum isospring_model_kind {
  ISOSPRING_MODEL_NETWORK = 0, /* particles, springs, cell and strain-point terms */
  ISOSPRING_MODEL_REDUCED = 1  /* a subspace model: state = reduced coordinates */
};

/* Term kinds, as bits of a mask (isospring_model_set_terms) and as arguments of
 * isospring_model_term_count. */
enum isospring_term {
  ISOSPRING_TERM_SPRINGS = 1,      /* springs with their damping */
  ISOSPRING_TERM_CELL_VOLUME = 2,  /* "volumes" entries with "particles" and "kappa" */
  ISOSPRING_TERM_CELL_SHEAR = 4,   /* "volumes" entries with "particles" and "mu" */
  ISOSPRING_TERM_POINT_VOLUME = 8, /* "volumes" entries with "points" and "kappa" */
  ISOSPRING_TERM_POINT_SHEAR = 16, /* "volumes" entries with "points" and "mu" */
  ISOSPRING_TERM_REDUCED = 32,     /* the reduced model's Lambda and C_r */
  ISOSPRING_TERM_ALL = 63
};

/* Loads a model file. On failure returns NULL and writes a sentence naming the file, the field
 * and the fix into `error` (truncated to error_size bytes, always NUL-terminated; error may be
 * NULL). */
isospring_model* isospring_model_load(const char* path, char* error, size_t error_size);

/* The same from a document in memory (`source` names it in messages). */
isospring_model* isospring_model_parse(const char* text, size_t length, const char* source,
                                       char* error, size_t error_size);

/* Building a network in memory instead (an engine's own model, benchmarks): create it with its
 * particles, then add terms. Arguments are checked like a file's entries; on failure these
 * return NULL (create) or 0 (add, which then adds none of the call's terms) and write the reason,
 * naming the array and the entry, into `error`. Adds return 1 on success.
 * rest_positions: particles * dimension; masses: particles; fixed: particles flags or NULL. */
isospring_model* isospring_model_create(int dimension, size_t particles,
                                        const double* rest_positions, const double* masses,
                                        const unsigned char* fixed, char* error, size_t error_size);
/* ends: 2 particle indices per spring; damping may be NULL (none). */
int isospring_model_add_springs(isospring_model* model, size_t count, const int* ends,
                                const double* stiffness, const double* damping,
                                const double* rest_lengths, char* error, size_t error_size);
/* term: ISOSPRING_TERM_CELL_VOLUME (moduli = kappa) or ISOSPRING_TERM_CELL_SHEAR (mu);
 * corners: 2^dimension per cell in tensor order; rest_volumes: signed V0 per cell. */
int isospring_model_add_cells(isospring_model* model, int term, size_t count, const int* corners,
                              const double* moduli, const double* rest_volumes, char* error,
                              size_t error_size);
/* term: ISOSPRING_TERM_POINT_VOLUME or ISOSPRING_TERM_POINT_SHEAR; point k's particles are
 * particles[offsets[k] .. offsets[k + 1]) with gradients dR/dX (dimension numbers each) at the
 * same positions of `gradients`; offsets has count + 1 entries. */
int isospring_model_add_points(isospring_model* model, int term, size_t count,
                               const size_t* offsets, const int* particles, const double* gradients,
                               const double* moduli, const double* rest_volumes, char* error,
                               size_t error_size);

/* A reduced model from its arrays (docs/reduced_model.md): r basis vectors; eigenvalues (r),
 * damping C_r and step_inverse (r x r, row-major), basis Phi ((particles * dimension) x r,
 * row-major); fixed may be NULL. */
isospring_model* isospring_model_create_reduced(
    int dimension, size_t particles, const double* rest_positions, const unsigned char* fixed,
    size_t r, double timestep, const double* eigenvalues, const double* damping,
    const double* step_inverse, const double* basis, char* error, size_t error_size);

/* Frees a model (NULL is ignored). */
void isospring_model_free(isospring_model* model);

int isospring_model_kind(const isospring_model* model);
/* 2 (in-plane, z ignored) or 3. */
int isospring_model_dimension(const isospring_model* model);
size_t isospring_model_particle_count(const isospring_model* model);
/* Length of the state vectors: particles * dimension for a network, the basis size for a
 * reduced model. */
size_t isospring_model_state_size(const isospring_model* model);
/* Rest positions, particles * dimension numbers. */
const double* isospring_model_rest_positions(const isospring_model* model);
/* Particle masses [kg] (a network; NULL for a reduced model, whose file has none). */
const double* isospring_model_masses(const isospring_model* model);
/* 1 when the particle is held in place. */
int isospring_model_particle_fixed(const isospring_model* model, size_t particle);
/* Number of terms of one kind (one isospring_term bit); for ISOSPRING_TERM_REDUCED the basis
 * size. */
size_t isospring_model_term_count(const isospring_model* model, int term);

/* Which term kinds the evaluation functions include (a mask of isospring_term bits; all by
 * default). An engine that runs the springs itself (MuJoCo tendons) masks them out. */
void isospring_model_set_terms(isospring_model* model, int mask);
int isospring_model_terms(const isospring_model* model);

/* f = -dE/dx(x) plus the damping forces at velocity v (v may be NULL: no damping), over the
 * selected terms, written into f (overwritten; state size). Returns E(x) of those terms; NaN for
 * a NULL argument. One call per step. */
double isospring_model_forces(const isospring_model* model, const double* x, const double* v,
                              double* f);

/* The Jacobian-vector product of those forces: df = (df/dx) dx + (df/dv) dv at (x, v), written
 * into df (overwritten). v and dv may be NULL (no damping, or no velocity direction). -df for
 * dv = NULL is the tangent stiffness times dx: what a Krylov solver of an implicit step needs. */
void isospring_model_force_jvp(const isospring_model* model, const double* x, const double* v,
                               const double* dx, const double* dv, double* df);

/* Reduced models only (no effect on a network).
 * Time step dt [s] the file's step matrix was formed for (0 for a network). */
double isospring_model_timestep(const isospring_model* model);
/* g = Phi^T f: a force on the particles (particles * dimension) to reduced coordinates. */
void isospring_model_reduce_force(const isospring_model* model, const double* particle_force,
                                  double* g);
/* u = Phi q: the particles' displacements (particles * dimension) of reduced coordinates q. */
void isospring_model_expand(const isospring_model* model, const double* q, double* u);
/* One linearly implicit backward Euler step under the reduced force g, updating q and qdot in
 * place (docs/reduced_model.md, "The step"). */
void isospring_model_reduced_step(isospring_model* model, const double* g, double* q, double* qdot);

#ifdef __cplusplus
}
#endif

#endif /* ISOSPRING_RUNTIME_RUNTIME_H */
