//! Strokes a game paints while it runs, merged into the paint they change. A scene's
//! [`PaintEdits`] holds the few strokes painted since the last merge and one map of what the
//! earlier ones left, texel by texel: a scene painted a thousand times is as big, as quick to
//! clone and compare, and its paint as quick to make, as one painted once. The strokes a scene
//! file lists (`[[paint.stroke]]`) are the file's and stay in it; these are the run's.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use glam::Vec2;

use crate::paint::{PaintMap, Stroke};

/// How many strokes wait, painted one by one, before they are merged into the map of the
/// earlier ones: enough that a game painting a stroke each frame merges twice a second, few
/// enough that a scene with them is small to clone (a merge copies the whole map once).
pub const MERGE_AFTER: usize = 32;

/// How many merges back a renderer may lag and still paint only the strokes it has not: one
/// that lags further grows its paint anew from the merged map.
const HISTORY: usize = 8;

/// The strokes painted over a scene's paint while it runs: those since the last merge, in
/// order, and the map the ones before them left (shared between the scene's clones). Two
/// edits are equal where they paint the same strokes, merged or not.
#[derive(Clone, Debug, Default)]
pub struct PaintEdits {
    /// The strokes painted since the last merge, in the order they came (the field's own x
    /// and z, as a scene's strokes).
    pending: Vec<Stroke>,
    /// What the strokes before them left.
    merged: Option<Arc<MergedEdits>>,
}

/// The paint the merged strokes left, and which texels they changed.
#[derive(Debug)]
struct MergedEdits {
    /// Every texel's paint: a texel no stroke changed holds the paint beneath it when merged.
    map: PaintMap,
    /// Which texels a stroke changed (the rest follow the paint beneath them).
    edited: Vec<bool>,
    /// How many strokes are merged.
    strokes: u64,
    /// The serials of this merge and the ones before it, latest first, a few (a serial names
    /// a merge: how many strokes it held is `strokes` where it is the latest).
    history: Vec<u64>,
    /// What the paint beneath was made from (its `[paint]`, its kinds of grass, their files),
    /// so the next merge starts from this map where that is unchanged.
    beneath: Beneath,
}

/// What the paint beneath the edits is made from.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Beneath {
    pub(crate) paint: crate::paint::PaintParams,
    pub(crate) species: Vec<crate::species::Species>,
    pub(crate) contents: crate::content::Contents,
}

impl PaintEdits {
    /// Paint `stroke` after the others.
    pub fn paint(&mut self, stroke: Stroke) {
        self.pending.push(stroke);
    }

    /// Whether nothing was painted.
    pub fn is_empty(&self) -> bool {
        self.pending.is_empty() && self.merged.is_none()
    }

    /// How many strokes were painted in all.
    pub fn count(&self) -> u64 {
        self.merged_strokes() + self.pending.len() as u64
    }

    /// The strokes painted since the last merge.
    pub fn pending(&self) -> &[Stroke] {
        &self.pending
    }

    /// Whether enough strokes wait to be merged ([`MERGE_AFTER`]).
    pub fn wants_merging(&self) -> bool {
        self.pending.len() >= MERGE_AFTER
    }

    fn merged_strokes(&self) -> u64 {
        self.merged.as_ref().map_or(0, |m| m.strokes)
    }

    /// The strokes these edits paint after `old`'s where they carry on from them (the same
    /// strokes, then more; merged or not), an empty list where they paint the same; `None`
    /// where they went another way, or `old` saw too few of the strokes merged since.
    pub fn added_since<'a>(&'a self, old: &PaintEdits) -> Option<&'a [Stroke]> {
        let (was, now) = (old.merged_strokes(), self.merged_strokes());
        if now < was || !self.merged_after(old) {
            return None;
        }
        let seen = old.count().checked_sub(now)? as usize;
        let old_tail = &old.pending[(now - was) as usize..];
        (self.pending.get(..seen)? == old_tail).then(|| &self.pending[seen..])
    }

    /// Whether these edits' merged map is `old`'s or was merged after it.
    fn merged_after(&self, old: &PaintEdits) -> bool {
        match (&self.merged, &old.merged) {
            (_, None) => true,
            (None, Some(_)) => false,
            (Some(new), Some(old)) => new.history.contains(&old.history[0]),
        }
    }

    /// Put what the merged strokes changed over `map` (the paint beneath: the scene's maps and
    /// its file's strokes), each texel they changed where it is in `map`.
    pub fn overlay_onto(&self, map: &mut PaintMap) {
        if let Some(merged) = &self.merged {
            merged.overlay_onto(map, &mut []);
        }
    }

    /// Merge the strokes waiting into the map of the earlier ones. `beneath` is what the paint
    /// they are painted over is made from, `make` makes it (called only where the merged map's
    /// is not the same; where it fails nothing is merged); `species` the index of the kind a
    /// stroke names.
    pub(crate) fn merge<E>(
        &mut self,
        beneath: Beneath,
        make: impl FnOnce() -> Result<PaintMap, E>,
        species: impl Fn(&Stroke) -> Option<usize>,
    ) -> Result<(), E> {
        if self.pending.is_empty() {
            return Ok(());
        }
        let (mut map, mut edited) = match &self.merged {
            Some(m) if m.beneath == beneath => (m.map.clone(), m.edited.clone()),
            held => {
                let mut map = make()?;
                let mut edited = vec![false; map.texels.len()];
                if let Some(m) = held {
                    m.overlay_onto(&mut map, &mut edited);
                }
                (map, edited)
            }
        };
        for stroke in &self.pending {
            map.paint_stroke_marking(stroke, species(stroke), |i| edited[i] = true);
        }
        static SERIALS: AtomicU64 = AtomicU64::new(1);
        let strokes = self.count();
        let mut history = vec![SERIALS.fetch_add(1, Ordering::Relaxed)];
        if let Some(m) = &self.merged {
            history.extend(m.history.iter().take(HISTORY - 1));
        }
        self.merged = Some(Arc::new(MergedEdits {
            map,
            edited,
            strokes,
            history,
            beneath,
        }));
        self.pending.clear();
        Ok(())
    }
}

impl MergedEdits {
    /// Put each texel a stroke changed over `map`, marking it in `edited` where that is as long
    /// as `map`'s texels: texel for texel where `map` is laid out as this one, else at each of
    /// `map`'s texels the nearest of this one's (a `[paint]` area or resolution changed).
    fn overlay_onto(&self, map: &mut PaintMap, edited: &mut [bool]) {
        let same = (map.min, map.max, map.size) == (self.map.min, self.map.max, self.map.size);
        let mut mark = |i: usize| {
            if let Some(e) = edited.get_mut(i) {
                *e = true;
            }
        };
        if same {
            for (i, _) in self.edited.iter().enumerate().filter(|(_, e)| **e) {
                map.texels[i] = self.map.texels[i];
                mark(i);
            }
            return;
        }
        let [per_unit, own_per_unit] = [map.texels_per_unit(), self.map.texels_per_unit()];
        let last = [self.map.size[0] - 1, self.map.size[1] - 1];
        for z in 0..map.size[1] {
            for x in 0..map.size[0] {
                let at = map.min + (Vec2::new(x as f32, z as f32) + 0.5) / per_unit;
                let own = ((at - self.map.min) * own_per_unit).floor();
                if own.min_element() < 0.0 || own.x > last[0] as f32 || own.y > last[1] as f32 {
                    continue;
                }
                let from = own.y as usize * self.map.size[0] as usize + own.x as usize;
                if self.edited[from] {
                    let i = (z * map.size[0] + x) as usize;
                    map.texels[i] = self.map.texels[from];
                    mark(i);
                }
            }
        }
    }
}

impl PartialEq for PaintEdits {
    fn eq(&self, other: &PaintEdits) -> bool {
        let same = |a: &PaintEdits, b: &PaintEdits| a.added_since(b).is_some_and(<[Stroke]>::is_empty);
        same(self, other) || same(other, self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;

    fn stroke(k: usize) -> Stroke {
        Stroke::circle(Vec2::new(k as f32 * 0.4 - 6.0, 1.0), 0.7).mow(0.2 + (k % 3) as f32 * 0.2)
    }

    fn painted(count: usize) -> Scene {
        let mut scene = Scene::default();
        (0..count).for_each(|k| scene.edits.paint(stroke(k)));
        scene
    }

    /// A scene's strokes merged paint what they painted waiting; a renderer that took the scene
    /// before the merge finds, after it, only the strokes it lacks, and painting them into the
    /// paint it holds makes the scene's paint; one that lags past the merge, or edits that went
    /// another way, find none: their field grows again.
    #[test]
    fn a_renderer_finds_the_strokes_it_lacks_across_a_merge() {
        let mut scene = painted(40);
        let taken = scene.clone();
        let waiting = scene.paint_map().unwrap();
        scene.merge_edits().unwrap();
        assert!(scene.edits.pending().is_empty() && scene.edits.count() == 40);
        assert!(
            scene.paint_map().unwrap() == waiting,
            "the merged strokes paint what they did waiting"
        );
        assert!(scene.edits == taken.edits && scene.grows_as(&taken));
        assert_eq!(scene.strokes_added_to(&taken), None, "nothing added");

        scene.edits.paint(stroke(40));
        scene.edits.paint(stroke(41));
        let added = scene.strokes_added_to(&taken).expect("two strokes added");
        assert_eq!(added, [stroke(40), stroke(41)]);
        let mut held = taken.paint_map().unwrap();
        scene.paint_strokes(&mut held, added);
        assert!(
            held == scene.paint_map().unwrap(),
            "the held paint with the strokes added is the scene's"
        );

        let lagging = painted(10);
        assert_eq!(scene.strokes_added_to(&lagging), None, "it lacks strokes merged since");
        assert!(!scene.grows_as(&lagging));

        let mut other = taken.clone();
        other.edits.paint(stroke(99));
        other.merge_edits().unwrap();
        scene.merge_edits().unwrap();
        assert!(other.edits != scene.edits && !other.grows_as(&scene));
        assert_eq!(other.strokes_added_to(&scene), None);
    }

    /// Edits carried to a scene whose paint area changed keep what they painted where they
    /// painted it (each texel of the new map the nearest of the old), and the rest of the
    /// ground takes the new paint.
    #[test]
    fn edits_keep_what_they_painted_over_a_new_paint_area() {
        let mut scene = painted(40);
        scene.merge_edits().unwrap();
        let mut wider = Scene::default();
        wider.paint.area = [-40.0, -40.0, 40.0, 40.0];
        wider.paint.resolution = 2.0;
        wider.edits = scene.edits.clone();
        let map = wider.paint_map().unwrap().unwrap().map.unwrap();
        let mowed = map.at(Vec2::new(-6.0, 1.0));
        assert!(mowed.length < 0.5, "the first stroke's mowing stays: {}", mowed.length);
        assert_eq!(map.at(Vec2::new(30.0, 30.0)).length, 1.0, "unpainted ground grows full");
    }
}
