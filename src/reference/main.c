/* bw_reference: an independent reference for blockwall's results.
 *
 *   bw_reference RESULT.h5 [-o REFERENCE.h5] [-exact]
 *
 * Reads the problem from a blockwall output file (geometry, stiffnesses,
 * supports and loads are all in it: /blocks/centroid, /blocks/prescribed,
 * /blocks/load, /interfaces/blocks, center, angle, length, kn, kt, root
 * attributes m and depth), solves it again in quadruple precision by a dense
 * (skyline) Cholesky of the condensed stiffness (reference.f90, written from
 * model.md without blockwall's kernels), and measures the file's
 * /blocks/displacement and /interfaces/stress against it. Prescribed dofs
 * are taken as zero: the output file does not hold prescribed values.
 * With -exact the reference is the limit m -> infinity of the model (the
 * exact interface stiffness), its stresses the linear field at the file's
 * portion midpoints: the converged limit of a refinement study.
 *
 * stdout: one `name value` line per measure (see STAT_NAMES); with -o, an
 * HDF5 file with /reference/displacement (B,3), /reference/stress (I,m,2),
 * /reference/resultant (I,3), /reference/relative (I,3: dt, dn, phi at G)
 * and the measures as attributes of /reference.
 * Errors: one line on stderr, exit 1 (bad input or file) or 2 (the
 * assembly is a mechanism: the stiffness is not positive definite). */
#include <hdf5.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { NSTATS = 22 };
/* stats[] of bw_reference_solve, in order */
static const char *const STAT_NAMES[NSTATS] = {
  "free_dofs",         "lambda_min",           "lambda_max",         "cond_schur",       "cond_mixed",
  "ref_correction",    "ref_residual",         "err_translation",    "err_rotation",     "err_stress",
  "err_scaled",        "err_scaled_q",         "err_scaled_r",       "residual",         "residual_equilibrium",
  "residual_compatibility", "residual_unscaled", "inverse_iterations", "skyline_entries", "ref_error_bound",
  "x_over_b",          "backward_error"};

void bw_reference_solve(int nb, int ni, int m, int exact, double depth, const double centroid[], const int8_t prescribed[],
                        const double load[], const int64_t pairs[], const double center[], const double angle[],
                        const double length[], const double kn[], const double kt[], int have_file, int have_stress,
                        const double q_file[], const double s_file[], double q_ref[], double s_ref[], double f_ref[],
                        double g_ref[], double stats[], int *status);

static void die(int code, const char *what, const char *path)
{
  fprintf(stderr, "bw_reference: error: %s%s%s\n", what, path ? ": " : "", path ? path : "");
  exit(code);
}

/* Dataset `name` of `count` elements read as `type`; 0 when it is absent
 * and optional. */
static int read_dataset(hid_t f, const char *name, hid_t type, size_t elsize, size_t count, void **out, int optional)
{
  hid_t    d, s;
  hssize_t n;

  *out = NULL;
  if (H5Lexists(f, name, H5P_DEFAULT) <= 0) {
    if (optional) return 0;
    die(1, "missing dataset", name);
  }
  d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0) die(1, "cannot open dataset", name);
  s = H5Dget_space(d);
  n = H5Sget_simple_extent_npoints(s);
  if (n < 0 || (size_t)n != count) die(1, "dataset has an unexpected size", name);
  *out = calloc(count ? count : 1, elsize);
  if (!*out) die(1, "out of memory reading", name);
  if (count && H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, *out) < 0) die(1, "cannot read dataset", name);
  H5Sclose(s);
  H5Dclose(d);
  return 1;
}

static hsize_t extent0(hid_t f, const char *name)
{
  hid_t   d, s;
  hsize_t dims[4] = {0, 0, 0, 0};

  if (H5Lexists(f, name, H5P_DEFAULT) <= 0) die(1, "missing dataset", name);
  d = H5Dopen2(f, name, H5P_DEFAULT);
  s = H5Dget_space(d);
  if (H5Sget_simple_extent_dims(s, dims, NULL) < 1) die(1, "dataset has no rows", name);
  H5Sclose(s);
  H5Dclose(d);
  return dims[0];
}

static void read_attr(hid_t f, const char *name, hid_t type, void *v)
{
  hid_t a;

  if (H5Aexists(f, name) <= 0) die(1, "missing root attribute", name);
  a = H5Aopen(f, name, H5P_DEFAULT);
  if (a < 0 || H5Aread(a, type, v) < 0) die(1, "cannot read root attribute", name);
  H5Aclose(a);
}

static void write_dataset(hid_t g, const char *name, int rank, const hsize_t *dims, const double *v)
{
  hid_t s = H5Screate_simple(rank, dims, NULL);
  hid_t d = H5Dcreate2(g, name, H5T_IEEE_F64LE, s, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (d < 0 || H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) < 0) die(1, "cannot write dataset", name);
  H5Dclose(d);
  H5Sclose(s);
}

int main(int argc, char **argv)
{
  const char *in = NULL, *out = NULL;
  hid_t       f;
  int         m, nb, ni, status, have_file, have_stress, exact = 0;
  double      depth, stats[NSTATS];
  double     *centroid, *load, *center, *angle, *length, *kn, *kt, *q_file, *s_file, *q_ref, *s_ref, *f_ref, *g_ref;
  int8_t     *prescribed;
  int64_t    *pairs;

  for (int a = 1; a < argc; a++) {
    if (!strcmp(argv[a], "-o") && a + 1 < argc) out = argv[++a];
    else if (!strcmp(argv[a], "-exact")) exact = 1;
    else if (argv[a][0] != '-' && !in) in = argv[a];
    else die(1, "usage: bw_reference RESULT.h5 [-o REFERENCE.h5] [-exact]", NULL);
  }
  if (!in) die(1, "usage: bw_reference RESULT.h5 [-o REFERENCE.h5] [-exact]", NULL);
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  f = H5Fopen(in, H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) die(1, "cannot open HDF5 file", in);
  nb = (int)extent0(f, "/blocks/centroid");
  ni = H5Lexists(f, "/interfaces/blocks", H5P_DEFAULT) > 0 ? (int)extent0(f, "/interfaces/blocks") : 0;
  read_attr(f, "m", H5T_NATIVE_INT, &m);
  read_attr(f, "depth", H5T_NATIVE_DOUBLE, &depth);
  if (m < 1 || !(depth > 0)) die(1, "root attributes m >= 1 and depth > 0 required", in);
  read_dataset(f, "/blocks/centroid", H5T_NATIVE_DOUBLE, sizeof(double), 2 * (size_t)nb, (void **)&centroid, 0);
  read_dataset(f, "/blocks/prescribed", H5T_NATIVE_INT8, 1, 3 * (size_t)nb, (void **)&prescribed, 0);
  read_dataset(f, "/blocks/load", H5T_NATIVE_DOUBLE, sizeof(double), 3 * (size_t)nb, (void **)&load, 0);
  read_dataset(f, "/interfaces/blocks", H5T_NATIVE_INT64, sizeof(int64_t), 2 * (size_t)ni, (void **)&pairs, 0);
  read_dataset(f, "/interfaces/center", H5T_NATIVE_DOUBLE, sizeof(double), 2 * (size_t)ni, (void **)&center, 0);
  read_dataset(f, "/interfaces/angle", H5T_NATIVE_DOUBLE, sizeof(double), (size_t)ni, (void **)&angle, 0);
  read_dataset(f, "/interfaces/length", H5T_NATIVE_DOUBLE, sizeof(double), (size_t)ni, (void **)&length, 0);
  read_dataset(f, "/interfaces/kn", H5T_NATIVE_DOUBLE, sizeof(double), (size_t)ni, (void **)&kn, 0);
  read_dataset(f, "/interfaces/kt", H5T_NATIVE_DOUBLE, sizeof(double), (size_t)ni, (void **)&kt, 0);
  have_file   = read_dataset(f, "/blocks/displacement", H5T_NATIVE_DOUBLE, sizeof(double), 3 * (size_t)nb, (void **)&q_file, 1);
  have_stress = read_dataset(f, "/interfaces/stress", H5T_NATIVE_DOUBLE, sizeof(double), 2 * (size_t)m * ni, (void **)&s_file, 1);
  H5Fclose(f);
  if (!q_file) q_file = calloc(3 * (size_t)nb, sizeof(double));
  if (!s_file) s_file = calloc(2 * (size_t)m * ni + 1, sizeof(double));
  q_ref = calloc(3 * (size_t)nb, sizeof(double));
  s_ref = calloc(2 * (size_t)m * ni + 1, sizeof(double));
  f_ref = calloc(3 * (size_t)ni + 1, sizeof(double));
  g_ref = calloc(3 * (size_t)ni + 1, sizeof(double));
  if (!q_file || !s_file || !q_ref || !s_ref || !f_ref || !g_ref) die(1, "out of memory", NULL);

  bw_reference_solve(nb, ni, m, exact, depth, centroid, prescribed, load, pairs, center, angle, length, kn, kt, have_file,
                     have_stress, q_file, s_file, q_ref, s_ref, f_ref, g_ref, stats, &status);
  if (status == 1) die(2, "the stiffness is not positive definite (a mechanism, or singular in real128)", in);
  if (status == 2) die(1, "the problem is too large for a dense real128 solve (profile over 5e7 entries)", in);
  if (status != 0) die(1, "inconsistent input (m, depth, lengths, stiffnesses or block indices)", in);

  for (int s = 0; s < NSTATS; s++) printf("%s %.6e\n", STAT_NAMES[s], stats[s]);
  printf("have_solution %d\nhave_stress %d\n", have_file, have_stress);
  if (out) {
    hid_t   o = H5Fcreate(out, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), g, s, a;
    hsize_t dq[2] = {(hsize_t)nb, 3}, ds[3] = {(hsize_t)ni, (hsize_t)m, 2}, df[2] = {(hsize_t)ni, 3};
    if (o < 0) die(1, "cannot create", out);
    g = H5Gcreate2(o, "reference", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    write_dataset(g, "displacement", 2, dq, q_ref);
    write_dataset(g, "stress", 3, ds, s_ref);
    write_dataset(g, "resultant", 2, df, f_ref);
    write_dataset(g, "relative", 2, df, g_ref);
    s = H5Screate(H5S_SCALAR);
    for (int k = 0; k < NSTATS; k++) {
      a = H5Acreate2(g, STAT_NAMES[k], H5T_IEEE_F64LE, s, H5P_DEFAULT, H5P_DEFAULT);
      if (a < 0 || H5Awrite(a, H5T_NATIVE_DOUBLE, &stats[k]) < 0) die(1, "cannot write attribute", STAT_NAMES[k]);
      H5Aclose(a);
    }
    H5Sclose(s);
    H5Gclose(g);
    if (H5Fclose(o) < 0) die(1, "cannot close", out);
  }
  free(centroid), free(prescribed), free(load), free(pairs), free(center), free(angle), free(length);
  free(kn), free(kt), free(q_file), free(s_file), free(q_ref), free(s_ref), free(f_ref), free(g_ref);
  return 0;
}
