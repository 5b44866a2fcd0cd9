//! One budget of Bezier blades for every grass entity ([`GrassBudget`]): where the fields ask
//! more together than it allows, each grows the same share of its blades ([`GrassShare`]),
//! said once.

use bevy::app::{App, PostUpdate};
use bevy::ecs::prelude::*;
use bevy::prelude::ReflectDefault;
use sward_core::Scene;

use crate::components::Grass;

/// The most Bezier blades — the blades with physics, near the eye — every [`Grass`](crate::Grass)
/// entity of the world holds together (each scene's `[field] blades`, or its streamed window's).
/// Where the fields ask more, each grows the same share of its blades (a streamed window no
/// fewer than reach past its hand-over), sparser, and a warning says so once; a field
/// spawned or changed shares the budget out again. The generated grass and the billboards
/// beyond are made each frame for what the camera sees and hold no blades. Default: no bound.
#[derive(Resource, Clone, Copy, Debug, PartialEq, Eq, bevy::reflect::Reflect)]
#[reflect(Resource, Default)]
pub struct GrassBudget {
    /// The most Bezier blades held together (`u32::MAX`: no bound).
    pub blades: u32,
}

impl Default for GrassBudget {
    fn default() -> Self {
        GrassBudget::UNBOUNDED
    }
}

impl GrassBudget {
    /// Every field grows the blades its scene asks.
    pub const UNBOUNDED: GrassBudget = GrassBudget { blades: u32::MAX };
}

/// The blades a [`Grass`] entity grows (its `[field] blades`) under the [`GrassBudget`]: set
/// by the plugin each frame (what its scene asks where the budget allows it), read by the
/// game (and shown in an inspector); a value set by hand is set again.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, Default, bevy::reflect::Reflect)]
#[reflect(Component, Default)]
pub struct GrassShare {
    /// The blades its field grows.
    pub blades: u32,
}

pub(crate) fn build(app: &mut App) {
    app.register_type::<GrassBudget>()
        .register_type::<GrassShare>()
        .init_resource::<GrassBudget>()
        .add_systems(
            PostUpdate,
            // After the scenes loaded this frame are taken: a share is of the grass drawn.
            share_budget
                .in_set(crate::GrassSystems)
                .after(crate::assets::grow_from_sources),
        );
}

/// Each grass entity's share of the budget, and where the budget cuts them, said once (until
/// it cuts otherwise).
pub(crate) fn share_budget(
    budget: Res<GrassBudget>,
    mut grass: Query<(Entity, &Grass, Option<&mut GrassShare>)>,
    mut commands: Commands,
    mut told: Local<Option<String>>,
) {
    let asked: Vec<Asked> = grass.iter().map(|(_, g, _)| asked_of(&g.scene)).collect();
    let (granted, said) = shares(&asked, budget.blades);
    for ((entity, _, share), blades) in grass.iter_mut().zip(granted) {
        match share {
            Some(mut share) => {
                share.set_if_neq(GrassShare { blades });
            }
            None => {
                commands.entity(entity).insert(GrassShare { blades });
            }
        }
    }
    if said.is_some() && *told != said {
        bevy::log::warn!("{}", said.as_deref().unwrap_or_default());
    }
    *told = said;
}

/// What `scene` asks of the budget.
fn asked_of(scene: &Scene) -> Asked {
    Asked {
        blades: scene.field.blades,
        held: scene.bezier_blades(),
        least: scene.least_streaming_blades().unwrap_or(0),
    }
}

/// What one field asks of the budget: the blades its scene asks (`[field] blades`), those it
/// holds of them (its Bezier blades: none where it draws none), and the fewest it can grow
/// with (a streamed window's least; 0 for a fixed field).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Asked {
    pub blades: u32,
    pub held: u32,
    pub least: u32,
}

/// How many blades (`[field] blades`) each field grows under `budget`: what it asks where the
/// blades held together fit, else the same share of it for each (at least its least, and one
/// blade), and the sentence to say where the budget cut them.
pub(crate) fn shares(asked: &[Asked], budget: u32) -> (Vec<u32>, Option<String>) {
    let held: u64 = asked.iter().map(|a| a.held as u64).sum();
    if held <= budget as u64 {
        return (asked.iter().map(|a| a.blades).collect(), None);
    }
    let share = budget as f64 / held as f64;
    let granted: Vec<u32> = asked
        .iter()
        .map(|a| match a.held {
            0 => a.blades,
            _ => ((a.blades as f64 * share).floor() as u32).max(a.least).max(1),
        })
        .collect();
    let percent = share * 100.0;
    let mut said = format!(
        "the grass entities hold {held} Bezier blades together, over GrassBudget's {budget}: each grows {percent:.0} % of its [field] blades, sparser"
    );
    let floors = asked
        .iter()
        .zip(&granted)
        .filter(|(a, &g)| a.held > 0 && g == a.least)
        .count();
    if floors > 0 {
        said += &format!(
            " ({floors} streamed no fewer than their window's least, so together they hold more than the budget)"
        );
    }
    (granted, Some(said))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fixed(blades: u32) -> Asked {
        Asked {
            blades,
            held: blades,
            least: 0,
        }
    }

    #[test]
    fn fields_within_the_budget_grow_what_they_ask() {
        let asked = [fixed(1000), fixed(3000)];
        assert_eq!(shares(&asked, 4000), (vec![1000, 3000], None));
        assert_eq!(shares(&asked, u32::MAX).0, vec![1000, 3000]);
    }

    #[test]
    fn fields_over_the_budget_each_grow_the_same_share_and_say_so() {
        let (granted, said) = shares(&[fixed(1000), fixed(3000)], 2000);
        assert_eq!(granted, vec![500, 1500]);
        let said = said.expect("said");
        assert!(
            said.contains("4000") && said.contains("2000") && said.contains("50 %"),
            "{said}"
        );
        assert!(!said.contains(". "), "one sentence: {said}");
    }

    #[test]
    fn a_field_without_bezier_blades_takes_nothing_and_a_window_keeps_its_least() {
        let generated = Asked {
            blades: 60_000,
            held: 0,
            least: 0,
        };
        let streamed = Asked {
            blades: 65_536,
            held: 65_536,
            least: 36_864,
        };
        let (granted, said) = shares(&[generated, fixed(65_536), streamed], 65_536);
        assert_eq!(granted, vec![60_000, 32_768, 36_864]);
        assert!(said.expect("said").contains("1 streamed no fewer"));
        // A budget of nothing still grows a blade a fixed field.
        assert_eq!(shares(&[fixed(10)], 0).0, vec![1]);
    }
}
