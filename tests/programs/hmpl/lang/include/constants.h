// Included by motion_util.h; the guard makes a second inclusion a no-op.
#ifndef CONSTANTS_H
#define CONSTANTS_H

#define MM_PER_COUNT 0.001
#define HOME_OFFSET 25

#endif
