// Helper header for lang/include_file.hmpl: a macro, a global and a function, and a
// nested #include of a path relative to this header's folder.

#include "constants.h"

#define CLAMP(v, lo, hi) ((v) < (lo) ? (lo) : (v) > (hi) ? (hi) : (v))

int util_calls = 0;

double ScaleToMm(int counts) {
    util_calls++;
    return counts * MM_PER_COUNT;
}
