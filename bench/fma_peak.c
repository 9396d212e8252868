/* Double-precision peak of one core (issue 23, BENCHMARKS.md): 12 independent chains of 512-bit
 * fused multiply-adds (8 doubles, 2 flops each), timed by the thread's CPU time so that other
 * processes on the machine do not count. Also measures the clock by a chain of dependent integer adds.
 * Run: gcc -O2 -mavx512f -mfma bench/fma_peak.c -o target/fma_peak && target/fma_peak */
#include <immintrin.h>
#include <stdio.h>
#include <time.h>
static double cpu(void){struct timespec t;clock_gettime(CLOCK_THREAD_CPUTIME_ID,&t);return t.tv_sec+1e-9*t.tv_nsec;}
int main(void){
  __m512d a[12]; __m512d m=_mm512_set1_pd(0.999999), c=_mm512_set1_pd(1e-7);
  for(int i=0;i<12;i++) a[i]=_mm512_set1_pd(i);
  long iters=200000000; double t0=cpu();
  for(long k=0;k<iters;k++){
    #pragma GCC unroll 12
    for(int i=0;i<12;i++) a[i]=_mm512_fmadd_pd(a[i],m,c);
  }
  double t=cpu()-t0; double s=0; double o[8];
  for(int i=0;i<12;i++){_mm512_storeu_pd(o,a[i]); s+=o[0];}
  double flops=iters*12.0*8*2;
  printf("%.1f GFLOP/s per CPU-second (FMA = 2 flops), %.3f s, check %g\n", flops/t*1e-9, t, s);
  long x=1; t0=cpu();
  for(long k=0;k<iters/2;k++){ __asm__ volatile(".rept 20\n\t add %0, %0\n\t .endr" : "+r"(x)); }
  printf("clock %.2f GHz (dependent adds per CPU-second; x=%ld)\n", iters/2*20.0/(cpu()-t0)*1e-9, x);
}
