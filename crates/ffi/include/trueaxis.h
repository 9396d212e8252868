/* trueaxis real-time corrector: C ABI (src/compensate/ffi.rs).
 *
 * Create a corrector from a machine TOML and an error-values TOML, then call trueaxis_correct once per
 * servo cycle with the axis positions (mm for linear axes, deg for rotary axes, canonical order
 * X Y Z U V W A B C restricted to the machine's axes); it writes the corrections to ADD to the
 * set-points (mm, deg). A call allocates no memory. Link with -ltrueaxis (the cdylib). */
#ifndef TRUEAXIS_H
#define TRUEAXIS_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct trueaxis_corrector trueaxis_corrector;

/* Return codes of trueaxis_correct. */
#define TRUEAXIS_OK 0
#define TRUEAXIS_BAD_LENGTH (-1)
#define TRUEAXIS_NOT_FINITE (-2)
#define TRUEAXIS_NOT_CONVERGED (-3)
#define TRUEAXIS_NULL_POINTER (-4)
/* A correction beyond the machine file's [limits] (default 1000 um linear, 10000 urad rotary): refused, never clipped. */
#define TRUEAXIS_BEYOND_LIMIT (-5)

/* NULL on failure; the reason is written to error (NUL-terminated, at most error_len bytes) when error is not NULL. */
trueaxis_corrector *trueaxis_corrector_new(const char *machine_path, const char *errors_path, char *error, size_t error_len);
void trueaxis_corrector_free(trueaxis_corrector *corrector);
/* Forget the previous call (after a jump of the axes; optional: a far jump only costs time). */
void trueaxis_corrector_reset(trueaxis_corrector *corrector);
/* Length of the positions and corrections arrays. */
int32_t trueaxis_corrector_axis_count(const trueaxis_corrector *corrector);
/* Length of the temperatures array (degC, the error model's sensors in file order). */
int32_t trueaxis_corrector_sensor_count(const trueaxis_corrector *corrector);
/* Letter of axis index ('X', ... 'C'), 0 when out of range. */
char trueaxis_corrector_axis_letter(const trueaxis_corrector *corrector, size_t index);
/* temperatures and directions (+1, -1, 0 per axis) may be NULL: 20 degC, at rest.
 * Returns TRUEAXIS_OK, or a negative code; on every code but TRUEAXIS_OK the corrections array is set to
 * all zeros (no correction, never the previous call's values), unless corrector or corrections is NULL.
 * Each call starts from the previous call's correction (a servo loop moves little per cycle) and
 * checks the residual on the exact chain (< 0.01 um); the result may differ from a cold solve by less
 * than that. trueaxis_corrector_reset forgets the previous call. */
int32_t trueaxis_correct(trueaxis_corrector *corrector, const double *positions, const double *temperatures,
                         const int8_t *directions, double *corrections);

#ifdef __cplusplus
}
#endif

#endif /* TRUEAXIS_H */
