//! Where a renderer's GPU memory goes: its allocations summed by name, largest first, as
//! `sward bench` writes them beside each case (`memory.csv`).

/// The `count` largest of `allocations` (name, bytes), largest first; those of one name summed
/// (a renderer names each of its buffers and images, several of a kind alike).
pub fn largest(allocations: Vec<(String, u64)>, count: usize) -> Vec<(String, u64)> {
    let mut by_name: Vec<(String, u64)> = Vec::new();
    for (name, bytes) in allocations {
        match by_name.iter_mut().find(|(n, _)| *n == name) {
            Some((_, sum)) => *sum += bytes,
            None => by_name.push((name, bytes)),
        }
    }
    by_name.sort_by(|a, b| b.1.cmp(&a.1).then_with(|| a.0.cmp(&b.0)));
    by_name.truncate(count);
    by_name
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn allocations_of_one_name_are_summed_and_the_largest_kept() {
        let named = |n: &str, b| (n.to_string(), b);
        let all = vec![
            named("lists", 10),
            named("blades", 64),
            named("lists", 70),
            named("eta", 4),
        ];
        assert_eq!(largest(all, 2), [named("lists", 80), named("blades", 64)]);
    }
}
