// An exclusive prefix sum, in place, over SCAN_BUFFER[base .. base + count), by one workgroup of
// SCAN_LANES invocations: each takes a run of values, the runs' sums are scanned across the
// workgroup, then each run is rewritten from where the runs before it end. In a fixed order, so
// the same whatever else runs. The including shader defines SCAN_BUFFER and SCAN_LANES (its
// workgroup size) and declares `shared uint scan_partial[SCAN_LANES]`.
void exclusive_scan(uint base, uint count) {
    uint lane = gl_LocalInvocationID.x;
    uint run = (count + SCAN_LANES - 1u) / SCAN_LANES;
    uint first = min(lane * run, count), last = min(first + run, count);
    uint sum = 0u;
    for (uint g = first; g < last; g++) {
        sum += SCAN_BUFFER[base + g];
    }
    scan_partial[lane] = sum;
    barrier();
    for (uint offset = 1u; offset < SCAN_LANES; offset <<= 1u) {
        uint add = lane >= offset ? scan_partial[lane - offset] : 0u;
        barrier();
        scan_partial[lane] += add;
        barrier();
    }
    uint before = scan_partial[lane] - sum;
    for (uint g = first; g < last; g++) {
        uint n = SCAN_BUFFER[base + g];
        SCAN_BUFFER[base + g] = before;
        before += n;
    }
}
