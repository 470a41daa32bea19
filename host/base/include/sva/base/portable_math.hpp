#pragma once
// The elementary functions that feed a result (a simulated reading, a map, an
// estimate, an eval's errors), computed by code of our own so that the same
// binary gives the same bits on every x86-64 CPU.
//
// Why not <cmath>: glibc picks FMA/AVX2 variants of exp, log, sin, cos, atan,
// atan2, acos, pow and others at load time by the CPU (and its versions
// differ). They differ from the SSE2 variants in the last bit on about 1 in
// 1,500 arguments (measured here: exp 724, sin 661, atan2 268, acos 275 and
// log 14 in 10^6 random arguments, with GLIBC_TUNABLES=glibc.cpu.hwcaps=
// -AVX2,-FMA against the default). A last-bit change in a contact's rotation
// steers the simulated contact controller elsewhere, so whole readings change.
//
// These are the fdlibm algorithms (as in FreeBSD's msun and musl): only +, -,
// *, / and sqrt, which IEEE 754 rounds exactly, compiled without contraction
// (-ffp-contract=off on sva_core and sva_sim). Accuracy: within 1 ulp of
// glibc's results over the ranges the engine uses, 2 for log2 and acos
// (tests/base/test_portable_math.cpp measures it); sin and cos reduce
// arguments exactly for |x| < 2^19 * pi/2 and less accurately beyond (still
// deterministically). Exact functions (sqrt, floor, ldexp, fmod, fabs) stay
// std::.
namespace sva::pmath {

double exp(double x);
double exp2(double x);
double log(double x);
double log2(double x);
double sin(double x);
double cos(double x);
void sincos(double x, double& s, double& c);
double atan(double x);
double atan2(double y, double x);
double acos(double x);
double hypot(double x, double y);

}  // namespace sva::pmath
