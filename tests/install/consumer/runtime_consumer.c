/* An engine's use of the installed runtime, in C: loads the model.json that the installed
 * `isospring calibrate` wrote, evaluates its forces at rest (zero: every spring at its rest
 * length, every term at its rest volume and strain) and along a stretch, where the
 * Jacobian-vector product must agree with a central difference of the forces; a missing file is
 * refused with its name. Exit 1 when a check fails.
 *
 *   runtime_consumer MODEL.json */
#include <isospring/runtime/runtime.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: runtime_consumer MODEL.json\n");
    return 2;
  }
  char error[1000];
  isospring_model* model = isospring_model_load(argv[1], error, sizeof(error));
  if (!model) {
    fprintf(stderr, "runtime_consumer: %s\n", error);
    return 1;
  }
  const size_t n = isospring_model_state_size(model);
  double* x = malloc(5 * n * sizeof(double));
  double *f = x + n, *dx = x + 2 * n, *df = x + 3 * n, *g = x + 4 * n;
  const double* rest = isospring_model_rest_positions(model);
  double largest = 0.0, stiff = 0.0, difference = 0.0;
  memcpy(x, rest, n * sizeof(double));
  isospring_model_forces(model, x, NULL, f);
  for (size_t e = 0; e < n; ++e) largest = fmax(largest, fabs(f[e]));
  /* A uniform 1% stretch along x. */
  for (size_t e = 0; e < n; ++e)
    dx[e] = (e % (size_t)isospring_model_dimension(model)) == 0 ? 0.01 * rest[e] : 0.0;
  isospring_model_force_jvp(model, x, NULL, dx, NULL, df);
  const double h = 1e-4;
  for (size_t e = 0; e < n; ++e) x[e] = rest[e] + h * dx[e];
  isospring_model_forces(model, x, NULL, f);
  for (size_t e = 0; e < n; ++e) x[e] = rest[e] - h * dx[e];
  isospring_model_forces(model, x, NULL, g);
  for (size_t e = 0; e < n; ++e) {
    const double central = (f[e] - g[e]) / (2 * h);
    stiff = fmax(stiff, fabs(central));
    difference = fmax(difference, fabs(df[e] - central));
  }
  const int missing = isospring_model_load("no-such-model.json", error, sizeof(error)) == NULL &&
                      strstr(error, "no-such-model.json") != NULL;
  printf(
      "runtime: %zu particles, %zu springs; |f| at rest %.3g, JVP vs central difference %.3g "
      "of %.3g; missing file refused: %s\n",
      isospring_model_particle_count(model),
      isospring_model_term_count(model, ISOSPRING_TERM_SPRINGS), largest, difference, stiff,
      missing ? "yes" : "no");
  const int ok = stiff > 0 && largest <= 1e-9 * stiff && difference <= 1e-6 * stiff && missing;
  free(x);
  isospring_model_free(model);
  return ok ? 0 : 1;
}
