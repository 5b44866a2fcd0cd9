//! What sward has allocated on the GPU against the most it may: the device's largest
//! device-local heap, or a smaller budget the user set (`--gpu-memory`) to see how sward copes
//! with a smaller GPU. Buffers and images reserve their bytes here before they allocate, so
//! running out is found before the driver is asked, and an error can name what still fits.

use std::sync::atomic::{AtomicU64, Ordering};

use ash::vk;

/// GPU memory in use, against the most that may be.
pub struct MemoryMeter {
    limit: u64,
    used: AtomicU64,
}

impl MemoryMeter {
    /// A meter for a device whose heaps are `heaps`, capped at `budget` bytes where given.
    pub fn new(heaps: &vk::PhysicalDeviceMemoryProperties, budget: Option<u64>) -> MemoryMeter {
        let device_local = heaps.memory_heaps[..heaps.memory_heap_count as usize]
            .iter()
            .filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
            .map(|h| h.size)
            .max()
            .unwrap_or(u64::MAX);
        MemoryMeter {
            limit: budget.map_or(device_local, |b| b.min(device_local)),
            used: AtomicU64::new(0),
        }
    }

    /// Count `bytes` as allocated if they fit under the limit; false (nothing counted) if not.
    pub fn reserve(&self, bytes: u64) -> bool {
        self.used
            .try_update(Ordering::AcqRel, Ordering::Acquire, |used| {
                used.checked_add(bytes).filter(|&total| total <= self.limit)
            })
            .is_ok()
    }

    /// Give back bytes an earlier `reserve` counted.
    pub fn release(&self, bytes: u64) {
        self.used.fetch_sub(bytes, Ordering::AcqRel);
    }

    /// Bytes allocated now.
    pub fn used(&self) -> u64 {
        self.used.load(Ordering::Acquire)
    }

    /// Bytes that may still be allocated.
    pub fn free(&self) -> u64 {
        self.limit.saturating_sub(self.used())
    }

    /// The most that may ever be allocated at once.
    pub fn limit(&self) -> u64 {
        self.limit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn heaps(sizes: &[(u64, vk::MemoryHeapFlags)]) -> vk::PhysicalDeviceMemoryProperties {
        let mut p = vk::PhysicalDeviceMemoryProperties {
            memory_heap_count: sizes.len() as u32,
            ..Default::default()
        };
        for (i, &(size, flags)) in sizes.iter().enumerate() {
            p.memory_heaps[i] = vk::MemoryHeap { size, flags };
        }
        p
    }

    #[test]
    fn the_largest_device_local_heap_is_the_limit_unless_a_budget_is_smaller() {
        let p = heaps(&[
            (64 << 30, vk::MemoryHeapFlags::empty()),
            (8 << 30, vk::MemoryHeapFlags::DEVICE_LOCAL),
            (256 << 20, vk::MemoryHeapFlags::DEVICE_LOCAL),
        ]);
        assert_eq!(MemoryMeter::new(&p, None).limit(), 8 << 30);
        assert_eq!(MemoryMeter::new(&p, Some(100 << 20)).limit(), 100 << 20);
        assert_eq!(MemoryMeter::new(&p, Some(100 << 30)).limit(), 8 << 30);
    }

    #[test]
    fn a_reservation_past_the_limit_counts_nothing() {
        let meter = MemoryMeter::new(&heaps(&[(1000, vk::MemoryHeapFlags::DEVICE_LOCAL)]), None);
        assert!(meter.reserve(600));
        assert!(!meter.reserve(401));
        assert_eq!(meter.used(), 600);
        assert!(meter.reserve(400));
        assert_eq!(meter.free(), 0);
        meter.release(1000);
        assert_eq!(meter.free(), 1000);
    }
}
