/* DAQP on the frames of a `sulcus-cli qp-gen` file, integrated as an engine
 * would: one workspace per sequence (set up on its first frame), and on every
 * later frame the new constraint matrix, linear term and bounds given to it with
 * daqp_update_ldp (the Hessian, fixed, keeps its factor), then solved warm from
 * the previous frame's working set. Times are per frame, measured here around the
 * update and the solve (setup and solve for a sequence's first frame). Built by
 * scripts/bench.sh against DAQP's C sources, with Sulcus's release flags.
 *
 * Each frame: min 1/2 (q - q_h)' G (q - q_h)  s.t.  A q >= b, G diagonal:
 * H = G, f = -G q_h, b <= A q <= +inf.
 *
 * Usage: daqp_bench QP_FILE SULCUS_SOLUTIONS SULCUS_MEDIAN_US SULCUS_P99_US
 * Prints one line of figures (the same as scripts/daqp_bench.py prints). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "api.h"
#include "constants.h"
#include "utils.h"

static double Now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e6 + (double)t.tv_nsec / 1e3;
}

static int Compare(const void* a, const void* b) {
  const double x = *(const double*)a, y = *(const double*)b;
  return (x > y) - (x < y);
}

static double Percentile(const double* sorted, size_t n, double q) {
  size_t i = (size_t)(q * (double)n);
  return sorted[i < n ? i : n - 1];
}

static void* ReadAll(const char* path, size_t* size) {
  FILE* f = fopen(path, "rb");
  if (!f) {
    fprintf(stderr, "%s: cannot open\n", path);
    exit(1);
  }
  fseek(f, 0, SEEK_END);
  *size = (size_t)ftell(f);
  fseek(f, 0, SEEK_SET);
  void* data = malloc(*size ? *size : 1);
  if (fread(data, 1, *size, f) != *size) {
    fprintf(stderr, "%s: cannot read\n", path);
    exit(1);
  }
  fclose(f);
  return data;
}

int main(int argc, char** argv) {
  if (argc != 5) {
    fprintf(stderr, "usage: daqp_bench QP_FILE SULCUS_SOLUTIONS MEDIAN_US P99_US\n");
    return 2;
  }
  size_t size = 0, sol_size = 0;
  unsigned char* data = ReadAll(argv[1], &size);
  const double* ours = ReadAll(argv[2], &sol_size);
  const double ours_median = atof(argv[3]), ours_p99 = atof(argv[4]);
  int head[4];
  if (size < 16) {
    fprintf(stderr, "%s: too short for a QP file\n", argv[1]);
    return 1;
  }
  memcpy(head, data, sizeof head);
  const int n = head[0], m = head[1], seqs = head[2], frames = head[3];
  const size_t stride = (size_t)n * (1 + (size_t)m) + (size_t)m;
  if (n <= 0 || m <= 0 || seqs <= 0 || frames <= 0 ||
      size != 16 + 8 * ((size_t)n + (size_t)seqs * frames * stride) ||
      sol_size != 8 * (size_t)seqs * frames * n) {
    fprintf(stderr, "%s: sizes do not match its header\n", argv[1]);
    return 1;
  }
  const double* g = (const double*)(data + 16);
  const double* body = g + n;

  double* H = calloc((size_t)n * n, sizeof(double));
  for (int i = 0; i < n; ++i) H[i * n + i] = g[i];
  double* f = malloc(sizeof(double) * n);
  double* A = malloc(sizeof(double) * (size_t)m * n);
  double* bl = malloc(sizeof(double) * m);
  double* bu = malloc(sizeof(double) * m);
  for (int i = 0; i < m; ++i) bu[i] = 1e30;
  int* sense = calloc((size_t)m, sizeof(int));
  double* x = malloc(sizeof(double) * n);
  double* lam = malloc(sizeof(double) * m);
  double* times = malloc(sizeof(double) * (size_t)seqs * frames);
  double* solves = malloc(sizeof(double) * (size_t)seqs * frames);  // daqp_solve alone
  size_t count = 0;
  long iterations = 0;
  int failures = 0;
  double worst = 0;

  for (int s = 0; s < seqs; ++s) {
    DAQPProblem qp = {0};
    qp.n = n;
    qp.m = m;
    qp.ms = 0;
    qp.H = H;
    qp.f = f;
    qp.A = A;
    qp.blower = bl;
    qp.bupper = bu;
    qp.sense = sense;
    memset(sense, 0, sizeof(int) * m);
    DAQPWorkspace work;
    memset(&work, 0, sizeof work);
    for (int t = 0; t < frames; ++t) {
      const double* frame = body + ((size_t)s * frames + t) * stride;
      const double* qh = frame;
      const double* fa = frame + n;
      const double* fb = frame + n + (size_t)n * m;
      // The frame's rows are copied into the problem's buffers before the clock
      // starts, as `qp-bench` copies them for Sulcus (an engine has just written
      // them: they are in cache); the linear term is formed on the clock.
      memcpy(A, fa, sizeof(double) * (size_t)m * n);
      memcpy(bl, fb, sizeof(double) * m);
      const double t0 = Now();
      for (int i = 0; i < n; ++i) f[i] = -g[i] * qh[i];
      int flag;
      if (t == 0) {
        flag = setup_daqp(&qp, &work, NULL);
      } else {
        flag = daqp_update_ldp(DAQP_UPDATE_M + DAQP_UPDATE_v + DAQP_UPDATE_d, &work, &qp);
      }
      DAQPResult res;
      memset(&res, 0, sizeof res);
      res.x = x;
      res.lam = lam;
      const double t1 = Now();
      if (flag >= 0) daqp_solve(&res, &work);
      const double t2 = Now();
      solves[count] = t2 - t1;
      times[count++] = t2 - t0;
      if (flag < 0 || res.exitflag != DAQP_EXIT_OPTIMAL) {
        ++failures;
        continue;
      }
      iterations += res.iter;
      const double* want = ours + ((size_t)s * frames + t) * n;
      for (int i = 0; i < n; ++i) {
        const double d = fabs(x[i] - want[i]);
        if (d > worst) worst = d;
      }
    }
    free_daqp_workspace(&work);
    free_daqp_ldp(&work);
  }
  qsort(times, count, sizeof(double), Compare);
  qsort(solves, count, sizeof(double), Compare);
  const double med = Percentile(times, count, 0.5), p99 = Percentile(times, count, 0.99);
  printf(
      "daqp-c update+solve median %.2f us, p99 %.2f us (daqp_solve alone %.2f / %.2f); "
      "iterations mean %.2f; failures %d; "
      "sulcus %.2f / %.2f us; ratio sulcus/daqp median %.2f, p99 %.2f; largest solution "
      "difference %.1e\n",
      med, p99, Percentile(solves, count, 0.5), Percentile(solves, count, 0.99),
      (double)iterations / (double)(count - failures), failures, ours_median,
      ours_p99, ours_median / med, ours_p99 / p99, worst);
  return 0;
}
