#pragma once
// SVA_HOT_PATH marks the few functions where the CPU reference spends its time
// (the per-match vote loop, the fold's integer log2). On x86-64 they are
// compiled three times, for the baseline ISA, for x86-64-v3 (AVX2, BMI2,
// LZCNT) and for x86-64-v4 (AVX-512: 16-lane vectors and twice the
// registers for the samples' loops), with every call inside inlined (flatten: the
// vote math must be compiled for the clone, not called in its baseline build),
// and the loader picks the clone the CPU can run (GCC's target_clones, an
// ifunc). The clones give the same bits: -ffp-contract=off forbids fusing
// multiply-adds and nothing reassociates float sums, so the wider instructions
// change only the speed (paper3d: v3 1.35x per update over the baseline on an
// AVX2 machine, v4 a further 1.07-1.14x on an AVX-512 one; docs/recognition.md).
// The tests compare the CPU with lavapipe bit for bit on whichever clone the
// machine runs; the determinism test's QEMU Haswell run checks the v3 clone on
// an AVX-512 machine. Elsewhere, and under AddressSanitizer (no ifuncs), it is
// empty.
// SVA_NO_TARGET_CLONES (a compile definition) builds the baseline alone, to test it on an AVX2 machine.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__) && \
    !defined(SVA_NO_TARGET_CLONES)
#define SVA_HOT_PATH __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default"), flatten))
#else
#define SVA_HOT_PATH
#endif
