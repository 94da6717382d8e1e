#pragma once
// VRV_FORCE_INLINE: for the few small functions of the discrete raycaster's per-sample loop that
// GCC leaves out of line at -O2/-O3 (the field's fetch, the classifier, the compositor), where a
// call per sample costs a measurable share of a 20 ns sample (studies/benchmarks/bench_discrete_baseline).
// VRV_FORCE_INLINE_LAMBDA goes between a lambda's parameter list and its body.  VRV_NOINLINE keeps
// a hot loop in its own function, where its values stay in registers (inlined into a large
// caller, they were spilled to the stack).
#if defined(__GNUC__) || defined(__clang__)
#define VRV_FORCE_INLINE inline __attribute__((always_inline))
#define VRV_FORCE_INLINE_LAMBDA __attribute__((always_inline))
#define VRV_NOINLINE __attribute__((noinline))
#else
#define VRV_FORCE_INLINE inline
#define VRV_FORCE_INLINE_LAMBDA
#define VRV_NOINLINE
#endif
