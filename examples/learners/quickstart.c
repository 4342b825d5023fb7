/* A first learner in C (C99, the standard library only): dead reckoning with the
 * command as the velocity (A0), and a straight-line sensor model fitted to it by
 * least squares over every reading. The protocol is JSON lines on stdin and
 * stdout (book: "The process protocol"); logs go to stderr. The host's messages
 * are flat objects of numbers and one string, so a field is found by its key.
 *
 *   cc -O2 -o target/quickstart examples/learners/quickstart.c
 *   cargo run --release --example train -- --learner exec:target/quickstart
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The number after "key": in a line; 0 when the key is missing. */
static double field(const char *line, const char *key) {
    char pattern[64];
    snprintf(pattern, sizeof pattern, "\"%s\":", key);
    const char *at = strstr(line, pattern);
    return at ? strtod(at + strlen(pattern), NULL) : 0.0;
}

static int is_type(const char *line, const char *type) {
    char pattern[64];
    snprintf(pattern, sizeof pattern, "\"type\":\"%s\"", type);
    return strstr(line, pattern) != NULL;
}

int main(void) {
    static char line[1 << 16];
    double x = 0, n = 0, su = 0, sx = 0, suu = 0, sux = 0;
    printf("{\"type\":\"hello\",\"protocol\":1,\"name\":\"quickstart-c\","
           "\"about\":\"dead reckoning with A0, a straight-line sensor model by least squares\","
           "\"settings\":[]}\n");
    fflush(stdout);
    while (fgets(line, sizeof line, stdin)) {
        if (is_type(line, "command")) {
            x += field(line, "command") * field(line, "dt_s");
        } else if (is_type(line, "reading")) {
            double u = field(line, "obs_px");
            n += 1; su += u; sx += x; suu += u * u; sux += u * x;
        } else if (is_type(line, "query")) {
            double det = n * suu - su * su;
            if (n < 2 || det <= 1e-9 * fmax(1.0, n * suu)) {
                printf("{\"type\":\"models\",\"action\":[0,1],\"sensor\":null,\"x_a\":%.17g,\"x_s\":null}\n", x);
            } else {
                double s1 = (n * sux - su * sx) / det, s0 = (sx - s1 * su) / n;
                printf("{\"type\":\"models\",\"action\":[0,1],\"sensor\":[%.17g,%.17g],\"x_a\":%.17g,\"x_s\":null}\n",
                       s0, s1, x);
            }
            fflush(stdout);
        } else if (is_type(line, "end")) {
            return 0;
        } else if (!is_type(line, "settings")) {
            fprintf(stderr, "quickstart-c: unexpected line: %s", line);
            return 1;
        }
    }
    return 0;
}
