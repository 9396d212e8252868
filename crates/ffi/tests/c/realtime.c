/* Calls the trueaxis real-time corrector through its C ABI: prints the corrections of the poses read
 * from stdin (one pose per line, axis_count numbers), one line each, or the error and exit 1. */
#include <stdio.h>
#include "trueaxis.h"

int main(int argc, char **argv) {
    char error[512];
    if (argc != 3) {
        fprintf(stderr, "usage: %s MACHINE.toml ERRORS.toml < poses\n", argv[0]);
        return 2;
    }
    trueaxis_corrector *c = trueaxis_corrector_new(argv[1], argv[2], error, sizeof error);
    if (c == NULL) {
        printf("error: %s\n", error);
        return 1;
    }
    int n = trueaxis_corrector_axis_count(c);
    double positions[9], corrections[9];
    int8_t directions[9];
    printf("axes %d sensors %d first %c\n", n, trueaxis_corrector_sensor_count(c), trueaxis_corrector_axis_letter(c, 0));
    for (;;) {
        for (int k = 0; k < n; k++) {
            if (scanf("%lf", &positions[k]) != 1) {
                trueaxis_corrector_free(c);
                return 0;
            }
            directions[k] = 0;
        }
        int rc = trueaxis_correct(c, positions, NULL, directions, corrections);
        printf("rc %d", rc);
        for (int k = 0; k < n; k++) printf(" %.12e", corrections[k]);
        printf("\n");
    }
}
