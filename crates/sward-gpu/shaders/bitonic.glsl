// A bitonic sort, ascending, of the first n words (a power of two, bitonic_size) of the shared
// array SORT_KEYS, by the whole workgroup: every invocation calls it, after the keys are
// written and a barrier. Unique keys sort to the same order every run. The including shader
// defines SORT_KEYS after declaring the array.

// The power of two, at least 2, that `count` keys are sorted over (the rest padded to sort last).
uint bitonic_size(uint count) {
    return count <= 2u ? 2u : 1u << (findMSB(count - 1u) + 1);
}

void bitonic_sort(uint n) {
    for (uint k = 2u; k <= n; k <<= 1u) {
        for (uint j = k >> 1u; j > 0u; j >>= 1u) {
            for (uint t = gl_LocalInvocationID.x; t < n / 2u; t += gl_WorkGroupSize.x) {
                uint lo = 2u * j * (t / j) + t % j;
                uint hi = lo + j;
                uint a = SORT_KEYS[lo];
                uint c = SORT_KEYS[hi];
                if ((a > c) == ((lo & k) == 0u)) {
                    SORT_KEYS[lo] = c;
                    SORT_KEYS[hi] = a;
                }
            }
            barrier();
        }
    }
}
