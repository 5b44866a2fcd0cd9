// How a blade joins its workgroup's run of its distance bucket (cull.wgsl, count and place
// passes) where the device has subgroups: neighbouring blades mostly share a bucket, so the
// lanes of a subgroup in its first lane's bucket take their places with one workgroup atomic
// (their ranks by a prefix sum), and only the others add one each. Called by every invocation
// in uniform control flow (`k` NOT_DRAWN for one without a listed blade; `lane` its index in
// the workgroup). The blade's place in the run. Needs subgroups.wgsl first.
fn join_bucket(k: u32, lane: u32) -> u32 {
    let first = subgroupBroadcastFirst(k);
    let together = k == first && k != NOT_DRAWN;
    let rank = subgroupExclusiveAdd(select(0u, 1u, together));
    let joined = subgroupAdd(select(0u, 1u, together));
    var base = 0u;
    // The subgroup's first lane (the one whose bucket `first` is) takes the run's places.
    if (subgroupBroadcastFirst(lane) == lane && joined > 0u) {
        base = atomicAdd(&group_counts[first], joined);
    }
    base = subgroupBroadcastFirst(base);
    if (together) {
        return base + rank;
    }
    if (k == NOT_DRAWN) {
        return 0u;
    }
    return atomicAdd(&group_counts[k], 1u);
}
