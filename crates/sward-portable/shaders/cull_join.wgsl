// How a blade joins its workgroup's run of its distance bucket (cull.wgsl, count and place
// passes), in WebGPU's core: one workgroup atomic per blade. Called by every invocation (`k`
// NOT_DRAWN for one without a listed blade; `lane`, its index in the workgroup, unused here).
// The blade's place in the run.
fn join_bucket(k: u32, lane: u32) -> u32 {
    if (k == NOT_DRAWN) {
        return 0u;
    }
    return atomicAdd(&group_counts[k], 1u);
}
