// Included by include/w50_include.pdl (manual §2.5.6, W50).
#long common_var;
#define COMMON_INIT common_var = 41;
