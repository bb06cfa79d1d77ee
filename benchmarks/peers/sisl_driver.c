/* Runs one SISL data-reduction routine on samples read from stdin, for
 * benchmarks/peers/sisl.py.  Written for sketchanim; links Debian's libsisl-dev.
 *
 * usage: sisl_driver s1961 DIM ORDER AFCTOL EPS...   (stdin: n, times[n], points[n*DIM])
 *        sisl_driver s1940 DIM ORDER EPS...          (same input; the start curve is the
 *                                                     paper's: samples as control polygon)
 * stdout (binary, native endianness): int32 n_coef, int32 order,
 *        double knots[n_coef+order], double coef[n_coef*DIM], double maxerr[DIM],
 *        double seconds (wall time of the SISL call alone).
 * exit status: 0 ok, 2 bad usage or input, 3 SISL reported an error. */
#include <sisl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int read_exact(void *buf, size_t size, size_t count) {
  return fread(buf, size, count, stdin) == count;
}

static SISLCurve *paper_start_curve(const double *times, double *points, int n, int dim,
                                    int order) {
  /* knots: first time `order` times, times[order/2 .. n-order+order/2-1], last time
   * `order` times: n coefficients, the samples themselves. */
  double *knots = malloc(sizeof(double) * (n + order));
  int i, j = 0;
  for (i = 0; i < order; i++) knots[j++] = times[0];
  for (i = order / 2; i < n - order + order / 2; i++) knots[j++] = times[i];
  for (i = 0; i < order; i++) knots[j++] = times[n - 1];
  SISLCurve *curve = newCurve(n, order, knots, points, 1, dim, 1);
  free(knots);
  return curve;
}

int main(int argc, char **argv) {
  if (argc < 5) {
    fprintf(stderr, "usage: sisl_driver s1961|s1940 DIM ORDER [AFCTOL] EPS...\n");
    return 2;
  }
  int is1961 = strcmp(argv[1], "s1961") == 0;
  int dim = atoi(argv[2]), order = atoi(argv[3]);
  int first_eps = is1961 ? 5 : 4;
  if (dim < 1 || order < 2 || argc != first_eps + dim) {
    fprintf(stderr, "sisl_driver: expected %d tolerances\n", dim);
    return 2;
  }
  double afctol = is1961 ? atof(argv[4]) : 0.0;
  double *eps = malloc(sizeof(double) * dim);
  for (int d = 0; d < dim; d++) eps[d] = atof(argv[first_eps + d]);

  int n;
  if (!read_exact(&n, sizeof(int), 1) || n < order) {
    fprintf(stderr, "sisl_driver: bad sample count\n");
    return 2;
  }
  double *times = malloc(sizeof(double) * n);
  double *points = malloc(sizeof(double) * n * dim);
  if (!read_exact(times, sizeof(double), n) || !read_exact(points, sizeof(double), (size_t)n * dim)) {
    fprintf(stderr, "sisl_driver: truncated input\n");
    return 2;
  }

  SISLCurve *result = NULL;
  double *maxerr = calloc(dim, sizeof(double));
  int stat = 0;
  double start = now();
  if (is1961) {
    s1961(points, n, dim, 3, times, eps, 0, 0, 1, afctol, 100, order, &result, maxerr, &stat);
  } else {
    SISLCurve *initial = paper_start_curve(times, points, n, dim, order);
    s1940(initial, eps, 0, 0, 1, 100, &result, maxerr, &stat);
    freeCurve(initial);
  }
  double seconds = now() - start;
  if (stat < 0 || result == NULL) {
    fprintf(stderr, "sisl_driver: SISL status %d\n", stat);
    return 3;
  }
  int nc = result->in, k = result->ik;
  fwrite(&nc, sizeof(int), 1, stdout);
  fwrite(&k, sizeof(int), 1, stdout);
  fwrite(result->et, sizeof(double), nc + k, stdout);
  fwrite(result->ecoef, sizeof(double), (size_t)nc * dim, stdout);
  fwrite(maxerr, sizeof(double), dim, stdout);
  fwrite(&seconds, sizeof(double), 1, stdout);
  freeCurve(result);
  free(times); free(points); free(eps); free(maxerr);
  return 0;
}
