// The file included by include/s2_5_6_include.pdl (PDL manual §2.5.6).
#long common_var;
#define COMMON_INIT common_var = 1;
