/* How many 512-bit and 256-bit double multiplies this CPU issues per nanosecond, and its clock:
 * the bound the SIMD arc engine meets (docs/guide/field.md, "Speed").
 *
 *   gcc -O2 -mavx512f scripts/vector-throughput.c -o /tmp/vt && /tmp/vt
 *
 * Eight independent chains of vmulpd (latency 4) can issue two per cycle; a CPU with one
 * 512-bit multiply port issues one. The clock is taken from a chain of dependent imul (latency
 * 3 on every current x86 core). Timings are wall-clock medians of five rounds. */
#include <immintrin.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#define N 50000000L

static double now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static double clock_ghz(void) {
    long x = 3;
    double t = now();
    for (long i = 0; i < N; i++)
        __asm__ volatile("imul %0, %0\n imul %0, %0\n imul %0, %0\n imul %0, %0\n imul %0, %0"
                         : "+r"(x));
    return 15.0 * N / (now() - t) / 1e9;
}

#define CHAINS(reg)                                                                              \
    "vmulpd %8, %0, %0\n vmulpd %8, %1, %1\n vmulpd %8, %2, %2\n vmulpd %8, %3, %3\n"           \
    "vmulpd %8, %4, %4\n vmulpd %8, %5, %5\n vmulpd %8, %6, %6\n vmulpd %8, %7, %7\n"

static double zmm_per_ns(void) {
    __m512d p[8], x = _mm512_set1_pd(1.0 + 1e-12);
    for (int k = 0; k < 8; k++) p[k] = _mm512_set1_pd(1.0 + k * 1e-9);
    double t = now();
    for (long i = 0; i < N; i++)
        __asm__ volatile(CHAINS(zmm) : "+v"(p[0]), "+v"(p[1]), "+v"(p[2]), "+v"(p[3]),
                         "+v"(p[4]), "+v"(p[5]), "+v"(p[6]), "+v"(p[7]) : "v"(x));
    return 8.0 * N / (now() - t) / 1e9;
}

static double ymm_per_ns(void) {
    __m256d p[8], x = _mm256_set1_pd(1.0 + 1e-12);
    for (int k = 0; k < 8; k++) p[k] = _mm256_set1_pd(1.0 + k * 1e-9);
    double t = now();
    for (long i = 0; i < N; i++)
        __asm__ volatile(CHAINS(ymm) : "+v"(p[0]), "+v"(p[1]), "+v"(p[2]), "+v"(p[3]),
                         "+v"(p[4]), "+v"(p[5]), "+v"(p[6]), "+v"(p[7]) : "v"(x));
    return 8.0 * N / (now() - t) / 1e9;
}

static int cmp(const void *a, const void *b) {
    double d = *(const double *)a - *(const double *)b;
    return (d > 0) - (d < 0);
}

static double median(double (*f)(void)) {
    double r[5];
    for (int k = 0; k < 5; k++) r[k] = f();
    qsort(r, 5, sizeof r[0], cmp);
    return r[2];
}

int main(void) {
    double ghz = median(clock_ghz), z = median(zmm_per_ns), y = median(ymm_per_ns);
    printf("clock %.2f GHz\n", ghz);
    printf("vmulpd zmm: %.2f per ns = %.2f per cycle (8 lanes: %.1f lane-multiplies per cycle)\n",
           z, z / ghz, 8 * z / ghz);
    printf("vmulpd ymm: %.2f per ns = %.2f per cycle (4 lanes: %.1f lane-multiplies per cycle)\n",
           y, y / ghz, 4 * y / ghz);
    return 0;
}
