/* Double-precision peak of one core (issue 23, BENCHMARKS.md): 12 independent chains of fused
 * multiply-adds of the widest vectors the CPU has (512-bit with AVX-512F: 8 doubles; else 256-bit
 * AVX2: 4 doubles; 2 flops each), timed by the thread's CPU time so that other processes on the
 * machine do not count. Also measures the clock by a chain of dependent integer adds.
 * Run: gcc -O2 -march=native bench/fma_peak.c -o target/fma_peak && target/fma_peak */
#include <immintrin.h>
#include <stdio.h>
#include <time.h>
#ifdef __AVX512F__
typedef __m512d vec;
#define WIDTH 8
#define SET1 _mm512_set1_pd
#define FMADD _mm512_fmadd_pd
#define STORE _mm512_storeu_pd
#define NAME "AVX-512F"
#else
typedef __m256d vec;
#define WIDTH 4
#define SET1 _mm256_set1_pd
#define FMADD _mm256_fmadd_pd
#define STORE _mm256_storeu_pd
#define NAME "AVX2"
#endif
static double cpu(void){struct timespec t;clock_gettime(CLOCK_THREAD_CPUTIME_ID,&t);return t.tv_sec+1e-9*t.tv_nsec;}
int main(void){
  vec a[12]; vec m=SET1(0.999999), c=SET1(1e-7);
  for(int i=0;i<12;i++) a[i]=SET1(i);
  long iters=200000000; double t0=cpu();
  for(long k=0;k<iters;k++){
    #pragma GCC unroll 12
    for(int i=0;i<12;i++) a[i]=FMADD(a[i],m,c);
  }
  double t=cpu()-t0; double s=0; double o[WIDTH];
  for(int i=0;i<12;i++){STORE(o,a[i]); s+=o[0];}
  double flops=iters*12.0*WIDTH*2;
  printf("%s: %.1f GFLOP/s per CPU-second (FMA = 2 flops), %.3f s, check %g\n", NAME, flops/t*1e-9, t, s);
  long x=1; t0=cpu();
  for(long k=0;k<iters/2;k++){ __asm__ volatile(".rept 20\n\t add %0, %0\n\t .endr" : "+r"(x)); }
  printf("clock %.2f GHz (dependent adds per CPU-second; x=%ld)\n", iters/2*20.0/(cpu()-t0)*1e-9, x);
}
