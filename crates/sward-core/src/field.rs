//! Field generation: blades placed on a plane with the SPEC §1 attribute ranges, seeded and
//! deterministic, with ids shuffled so that the distance test's id buckets are spatially random.

use crate::content::Contents;
use glam::{Vec2, Vec3};
use serde::{Deserialize, Serialize};

use bytemuck::Zeroable;

use crate::blade::Blade;
use crate::mesh::{Mesh, MeshError};
use crate::paint::{paint_at, painted_height, root_hash, GroundPaint};
use crate::rng::Pcg32;
use crate::species::{carried, species_of, Species};
use crate::validate::{Checks, Validate};

/// What the grass grows on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Surface {
    /// The plane y = 0, `field.size` of it grown.
    #[default]
    Plane,
    /// A whole sphere (a small planet); `field.blades` spread over its area.
    Sphere {
        /// Centre of the sphere.
        center: glam::Vec3,
        /// Radius of the sphere.
        radius: f32,
    },
    /// Rolling terrain of `size` (x, z) with hills up to `height`, a `resolution`² grid.
    Terrain {
        /// Extent in x and z.
        size: glam::Vec2,
        /// Height of the highest hills.
        height: f32,
        /// Vertices along each side of the grid.
        resolution: u32,
        /// Seed of the hills.
        seed: u64,
    },
    /// A mesh file, Wavefront OBJ or glTF 2.0 (.gltf, .glb), relative paths relative to the scene
    /// file, scaled about the origin.
    Mesh {
        /// The mesh file.
        path: String,
        /// Scale about the mesh's origin.
        scale: f32,
    },
    /// Terrain from a grey height map image (relative to the scene file): black at y = 0, white at
    /// `height`, spanning `size` (x, z).
    Heightmap {
        /// The grey PNG.
        path: String,
        /// Extent in x and z.
        size: glam::Vec2,
        /// Height of white.
        height: f32,
    },
}

impl Surface {
    /// The mesh the ground is, where it is one (terrain, height map, mesh file); `None` for the
    /// plane and the sphere. Its file is the one given in `contents` under its name, else read
    /// from disk. Fails only if a mesh or height-map file cannot be used.
    pub fn mesh(&self, contents: &crate::content::Contents) -> Result<Option<Mesh>, MeshError> {
        Ok(match self {
            Surface::Plane | Surface::Sphere { .. } => None,
            Surface::Terrain {
                size,
                height,
                resolution,
                seed,
            } => Some(Mesh::terrain(*size, *height, *resolution, *seed)),
            Surface::Mesh { path, scale } => Some(Mesh::load_from(contents, std::path::Path::new(path), *scale)?),
            Surface::Heightmap { path, size, height } => {
                let path = std::path::Path::new(path);
                Some(Mesh::heightmap_from(contents, path, *size, *height)?)
            }
        })
    }
}

/// How to grow a field, as the scene file's `[field]` table holds it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "reflect", derive(bevy_reflect::Reflect))]
#[serde(default, deny_unknown_fields)]
pub struct FieldDesc {
    /// Number of blades.
    pub blades: u32,
    /// Extent of the plane along x and z, centred on the origin.
    pub size: Vec2,
    /// Blade height range [min, max].
    pub height: [f32; 2],
    /// Blade half-width range [min, max].
    pub width: [f32; 2],
    /// Stiffness range [min, max].
    pub stiffness: [f32; 2],
    /// Seed of the blades' placement and variation.
    pub seed: u64,
    /// Stream the field around the eye (plane, terrain and height-map grounds): `blades` is then
    /// the budget of a window of tiles that follows the eye, each tile's blades made on the GPU
    /// from the instanced grass's grid (its density, heights, widths and seed; `stiffness` from
    /// here), so the Bezier blades and the instanced ones beyond them are the same blades. `size`,
    /// `height`, `width` and `seed` are the fixed field's alone. See `stream.rs`.
    pub stream: bool,
}

impl Default for FieldDesc {
    /// The course defaults: 2^13 blades on a 15 × 15 plane.
    fn default() -> Self {
        Self {
            blades: 1 << 13,
            size: Vec2::splat(15.0),
            height: [1.3, 2.5],
            width: [0.1, 0.14],
            stiffness: [7.0, 13.0],
            seed: 1,
            stream: false,
        }
    }
}

/// A grown field: the blades and the ground they stand on.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    /// Every blade, at rest, in tile order.
    pub blades: Vec<Blade>,
    /// Extent of the ground plane (x, z).
    pub size: Vec2,
    /// The mesh the blades grow on, where the ground is not the plane or a sphere.
    pub ground: Option<Mesh>,
    /// Runs of spatially close blades with their bounds (empty: one run of everything).
    pub tiles: Vec<crate::tiles::Tile>,
    /// Where the field streams: the window of tiles that follows the eye (its blades are made
    /// on the GPU; `blades` holds placeholders until then).
    pub stream: Option<crate::stream::StreamWindow>,
    /// The maps over the ground that say where grass grows and how tall (every technique the
    /// renderer draws reads them; the fixed blades here already obey them).
    pub paint: Option<GroundPaint>,
}

impl Field {
    /// `desc`'s blades on `surface`, cut into tiles. Fails only if a mesh file cannot be used.
    pub fn grow(surface: &Surface, desc: &FieldDesc) -> Result<Field, MeshError> {
        Field::grow_painted(surface, &Contents::default(), desc, None, &[])
    }

    /// `desc`'s blades on `surface` where `paint` lets them grow, as tall as it lets them, each
    /// of one of `species` (where there are any), cut into tiles (`paint.rs`: the density leaves
    /// out the blades its draw falls above, so the field holds fewer blades than `desc` asks for
    /// where density is below 1; `species.rs`: a blade keeps its place within `desc`'s ranges,
    /// carried into its species'). The ground's file is the one given in `contents`, if any.
    pub fn grow_painted(
        surface: &Surface,
        contents: &Contents,
        desc: &FieldDesc,
        paint: Option<&GroundPaint>,
        species: &[Species],
    ) -> Result<Field, MeshError> {
        let mut field = Field::grow_untiled(surface, contents, desc)?;
        if let Some(map) = paint {
            field.blades.retain(|b| grows(b, map));
            field.paint = Some(map.clone());
        }
        let area = match (&field.ground, surface) {
            (Some(mesh), _) => mesh.area(),
            (None, Surface::Sphere { radius, .. }) => 4.0 * std::f32::consts::PI * radius * radius,
            (None, _) => field.size.x * field.size.y,
        };
        field.tiles = crate::tiles::build(&mut field.blades, area);
        if paint.is_some() || !species.is_empty() {
            // By the blade's final id: the shaders key its colour, and so its species, by it.
            for (id, b) in field.blades.iter_mut().enumerate() {
                *b = shaped(b, id as u32, desc, paint, species);
            }
            field.tiles = crate::tiles::rebound(&field.blades, &field.tiles);
        }
        Ok(field)
    }

    /// The window of tiles `window` streams over `surface` (a plane, terrain or height map):
    /// every blade a placeholder the GPU replaces as the window's tiles are made, every tile's box
    /// empty until then. Fails only if a height-map file cannot be used (read from `contents`
    /// where given there).
    pub fn streamed(
        surface: &Surface,
        contents: &Contents,
        window: crate::stream::StreamWindow,
    ) -> Result<Field, MeshError> {
        let none = FieldDesc {
            blades: 0,
            ..FieldDesc::default()
        };
        let mut field = Field::grow_untiled(surface, contents, &none)?;
        field.blades = vec![Blade::zeroed(); window.blades() as usize];
        field.tiles = window.empty_tiles();
        field.size = Vec2::splat(window.tiles as f32 * window.tile_size());
        field.stream = Some(window);
        Ok(field)
    }

    /// `desc`'s blades on `surface`, in generation order (no tiles).
    fn grow_untiled(surface: &Surface, contents: &Contents, desc: &FieldDesc) -> Result<Field, MeshError> {
        let on_mesh = |mesh: Mesh| Field {
            blades: grow_on_mesh(&mesh, desc),
            size: mesh.footprint(),
            ground: Some(mesh),
            tiles: Vec::new(),
            stream: None,
            paint: None,
        };
        Ok(match (surface, surface.mesh(contents)?) {
            (_, Some(mesh)) => on_mesh(mesh),
            (Surface::Sphere { center, radius }, None) => Field::on_sphere(desc, *center, *radius),
            (_, None) => Field::on_plane(desc),
        })
    }

    /// Blades over a whole sphere, through the general mesh path (SPEC §2).
    pub fn on_sphere(desc: &FieldDesc, center: Vec3, radius: f32) -> Field {
        // About 2° per facet keeps the faceted surface within 0.1 % of the sphere.
        let mesh = Mesh::sphere(radius, 96, 192);
        let mut blades = grow_on_mesh(&mesh, desc);
        for b in &mut blades {
            let shift = center.extend(0.0);
            b.v0 += shift;
            b.v1 += shift;
            b.v2 += shift;
        }
        Field {
            blades,
            size: Vec2::splat(2.0 * radius),
            ground: None,
            tiles: Vec::new(),
            stream: None,
            paint: None,
        }
    }

    /// Blades on the plane y = 0. Roots are stratified (one per jittered grid cell, cells taken in
    /// shuffled order), so the field has no clumps or holes, and the shuffle leaves ids random.
    pub fn on_plane(desc: &FieldDesc) -> Field {
        let mut rng = Pcg32::new(desc.seed, 0x5eed);
        let count = desc.blades as usize;
        let (columns, rows) = plane_grid(count, desc.size);
        let mut cells: Vec<u32> = (0..(columns * rows) as u32).collect();
        rng.shuffle(&mut cells);

        let cell_size = desc.size / Vec2::new(columns as f32, rows as f32);
        let blades = cells[..count]
            .iter()
            .map(|&cell| {
                let (cx, cz) = ((cell as usize % columns) as f32, (cell as usize / columns) as f32);
                let jitter = Vec2::new(rng.next_f32(), rng.next_f32());
                let p = (Vec2::new(cx, cz) + jitter) * cell_size - desc.size * 0.5;
                Blade::at_rest(
                    Vec3::new(p.x, 0.0, p.y),
                    Vec3::Y,
                    rng.range(0.0, std::f32::consts::TAU),
                    rng.range(desc.height[0], desc.height[1]),
                    rng.range(desc.width[0], desc.width[1]),
                    rng.range(desc.stiffness[0], desc.stiffness[1]),
                )
            })
            .collect();
        Field {
            blades,
            size: desc.size,
            ground: None,
            tiles: Vec::new(),
            stream: None,
            paint: None,
        }
    }
}

/// The stratified grid of `count` blades on a plane of `size`: columns and rows of cells as
/// square as the size allows, at least `count` cells. Columns are held to 1..=count so that a
/// side too thin for a row of blades (which validation refuses, `FieldDesc::has_room`) still
/// gives a grid rather than more cells than a u32 counts.
fn plane_grid(count: usize, size: Vec2) -> (usize, usize) {
    let square = (count as f64 * size.x as f64 / size.y as f64).sqrt().ceil();
    let columns = if square.is_finite() {
        square.clamp(1.0, count.max(1) as f64) as usize
    } else {
        count.max(1)
    };
    (columns, count.div_ceil(columns).max(1))
}

/// Whether the paint lets blade `b` grow (its density draw, by its root).
fn grows(b: &Blade, paint: &GroundPaint) -> bool {
    let root = b.root();
    painted_height(root_hash(root.x, root.z), 1.0, paint.at(Vec2::new(root.x, root.z))) > 0.0
}

/// Blade `b` (grown within `desc`'s ranges), id `id`, at rest as its species (where there are
/// any) and as tall as the paint's length lets it.
fn shaped(b: &Blade, id: u32, desc: &FieldDesc, paint: Option<&GroundPaint>, species: &[Species]) -> Blade {
    let root = b.root();
    let place = paint_at(paint, Vec2::new(root.x, root.z));
    let (mut height, mut width, mut stiffness) = (b.height(), b.width(), b.stiffness());
    if !species.is_empty() {
        let weights: Vec<f32> = species.iter().zip(place.species).map(|(s, m)| s.weight * m).collect();
        let kind = &species[species_of(id, &weights)];
        height = carried(height, desc.height, kind.height);
        width = carried(width, desc.width, kind.width);
        stiffness = carried(stiffness, desc.stiffness, kind.stiffness);
    }
    Blade::at_rest(root, b.up(), b.orientation(), height * place.length, width, stiffness)
}

/// Blades on `mesh`, `desc.blades` of them with `desc`'s attribute ranges: triangles chosen in
/// proportion to their area (prefix sums + binary search), points uniform inside a triangle
/// (√r1 barycentrics), `up` = normalize(face normal + interpolated vertex normal). The width
/// direction comes from `up`'s tangent frame rotated by a uniform θ, as on the plane.
pub fn grow_on_mesh(mesh: &Mesh, desc: &FieldDesc) -> Vec<Blade> {
    let mut rng = Pcg32::new(desc.seed, 0x3e5);
    let mut cumulative = Vec::with_capacity(mesh.triangles.len());
    let mut total = 0.0f64;
    for t in 0..mesh.triangles.len() {
        total += 0.5 * mesh.face_cross(t).length() as f64;
        cumulative.push(total);
    }
    (0..desc.blades)
        .map(|_| {
            let pick = rng.next_f32() as f64 * total;
            let t = cumulative.partition_point(|&c| c <= pick).min(mesh.triangles.len() - 1);
            let (r1, r2) = (rng.next_f32().sqrt(), rng.next_f32());
            let weights = [1.0 - r1, r1 * (1.0 - r2), r1 * r2];
            let [a, b, c] = mesh.corners(t);
            let root = a * weights[0] + b * weights[1] + c * weights[2];
            let smooth: Vec3 = mesh.triangles[t]
                .iter()
                .zip(weights)
                .map(|(&i, w)| mesh.normals[i as usize] * w)
                .sum();
            let face = mesh.face_cross(t).normalize_or_zero();
            let up = (face + smooth.normalize_or_zero()).normalize_or(face);
            Blade::at_rest(
                root,
                up,
                rng.range(0.0, std::f32::consts::TAU),
                rng.range(desc.height[0], desc.height[1]),
                rng.range(desc.width[0], desc.width[1]),
                rng.range(desc.stiffness[0], desc.stiffness[1]),
            )
        })
        .collect()
}

impl Validate for Surface {
    fn validate(&self, c: &mut Checks) {
        match self {
            Surface::Sphere { center, radius } => c.check(
                *radius > 0.0 && radius.is_finite() && center.is_finite(),
                "surface.radius",
                radius,
                "a positive radius and a finite centre",
            ),
            Surface::Terrain {
                size,
                height,
                resolution,
                ..
            } => {
                check_relief(c, *size, *height);
                c.check(
                    (2..=2048).contains(resolution),
                    "surface.resolution",
                    resolution,
                    "2 to 2048 cells per side",
                );
            }
            Surface::Heightmap { size, height, .. } => check_relief(c, *size, *height),
            Surface::Mesh { scale, .. } => c.check(
                *scale > 0.0 && scale.is_finite(),
                "surface.scale",
                scale,
                "a positive scale",
            ),
            Surface::Plane => {}
        }
    }
}

/// A terrain's footprint and hill height.
fn check_relief(c: &mut Checks, size: Vec2, height: f32) {
    c.check(
        size.min_element() > 0.0 && size.is_finite(),
        "surface.size",
        size,
        "two positive extents [x, z]",
    );
    c.check(
        height.is_finite() && height >= 0.0,
        "surface.height",
        height,
        "a finite height ≥ 0",
    );
}

/// The most blades a field grows per square unit (1 mm apart): a denser field stacks its blades
/// into one another.
pub const MAX_FIELD_DENSITY: f32 = 1.0e6;

impl FieldDesc {
    /// Whether `size` has room for the blades on a plane (`Field::on_plane`): at most
    /// `MAX_FIELD_DENSITY` of them per square unit, and each side as long as a blade's spacing
    /// at least, so the stratified grid has a row and a column of blades. A side thinner than
    /// that would ask for more columns than blades.
    pub fn has_room(&self) -> bool {
        let (x, z) = (self.size.x as f64, self.size.y as f64);
        let area = x * z;
        let blades = self.blades.max(1) as f64;
        let spacing = (area / blades).sqrt();
        area > 0.0 && blades / area <= MAX_FIELD_DENSITY as f64 && x >= spacing && z >= spacing
    }
}

impl Validate for FieldDesc {
    fn validate(&self, c: &mut Checks) {
        c.check(
            self.blades >= 1 && self.blades <= crate::validate::MAX_BLADES,
            "field.blades",
            self.blades,
            "a whole number from 1 to 67108864 (2^26)",
        );
        c.check(
            self.size.x > 0.0 && self.size.y > 0.0 && self.size.is_finite(),
            "field.size",
            self.size,
            "two positive extents [x, z]",
        );
        c.check(
            self.has_room(),
            "field.size",
            self.size,
            format!(
                "extents [x, z] that leave room for the {} blades asked for: each side at least one blade's \
                 spacing (√(x·z / field.blades)) and at most {MAX_FIELD_DENSITY} blades per square unit",
                self.blades
            ),
        );
        c.range("field.height", self.height);
        c.range("field.width", self.width);
        c.check(
            self.width[1] <= self.height[0],
            "field.width",
            format!("[{}, {}]", self.width[0], self.width[1]),
            "widths no larger than the smallest height (field.height[0]); a blade wider than tall is not grass",
        );
        c.range("field.stiffness", self.stiffness);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_size_has_room_when_each_side_holds_a_blade_s_spacing_and_the_density_is_sane() {
        let field = |blades: u32, x: f32, z: f32| FieldDesc {
            blades,
            size: Vec2::new(x, z),
            ..FieldDesc::default()
        };
        assert!(field(60000, 24.0, 24.0).has_room());
        // A path of grass 100 units long and half a unit wide: rows of it across.
        assert!(field(60000, 100.0, 0.5).has_room());
        // A thousand units by a millimetre: 60000 blades are 4 mm apart, wider than the field.
        assert!(!field(60000, 1000.0, 0.001).has_room());
        assert!(!field(60000, 0.001, 1000.0).has_room());
        // 60000 blades on a square centimetre: 6 × 10^8 a square unit.
        assert!(!field(60000, 0.01, 0.01).has_room());
        assert!(!field(60000, 24.0, 1e-30).has_room());
        // One blade needs only its own square.
        assert!(field(1, 0.5, 0.5).has_room());
    }

    #[test]
    fn a_plane_too_thin_for_a_row_of_blades_still_grows_them() {
        // Validation refuses it (`has_room`); growing it anyway gave more grid cells than a u32
        // counts and panicked slicing them.
        for size in [Vec2::new(24.0, 1e-30), Vec2::new(1e-30, 24.0), Vec2::new(1e30, 1e-30)] {
            let desc = FieldDesc {
                blades: 600,
                size,
                ..FieldDesc::default()
            };
            assert_eq!(Field::on_plane(&desc).blades.len(), 600, "{size}");
        }
    }

    #[test]
    fn same_seed_gives_bit_identical_blades() {
        let desc = FieldDesc {
            blades: 500,
            ..FieldDesc::default()
        };
        let a = Field::on_plane(&desc);
        let b = Field::on_plane(&desc);
        assert_eq!(
            bytemuck::cast_slice::<_, u8>(&a.blades),
            bytemuck::cast_slice::<_, u8>(&b.blades)
        );
        let c = Field::on_plane(&FieldDesc { seed: 2, ..desc });
        assert_ne!(a.blades, c.blades);
    }

    #[test]
    fn attributes_stay_in_their_ranges_and_roots_on_the_plane() {
        let desc = FieldDesc {
            blades: 2000,
            ..FieldDesc::default()
        };
        let field = Field::on_plane(&desc);
        assert_eq!(field.blades.len(), 2000);
        for b in &field.blades {
            assert!(b.root().x.abs() <= 7.5 && b.root().z.abs() <= 7.5 && b.root().y == 0.0);
            assert!((1.3..2.5).contains(&b.height()));
            assert!((0.1..0.14).contains(&b.width()));
            assert!((7.0..13.0).contains(&b.stiffness()));
            assert_eq!(b.tip(), b.rest_tip());
        }
    }

    #[test]
    fn neighbouring_ids_are_not_neighbours_in_space_before_tiling() {
        let field = Field::on_plane(&FieldDesc {
            blades: 4000,
            ..FieldDesc::default()
        });
        let mean_step: f32 = field
            .blades
            .windows(2)
            .map(|w| w[0].root().distance(w[1].root()))
            .sum::<f32>()
            / 3999.0;
        // Random pairs on a 15 × 15 square are ~7.8 apart on average; a row-ordered grid would be ~0.24.
        assert!(mean_step > 5.0, "ids look spatially ordered: mean step {mean_step}");
    }

    #[test]
    fn density_is_even_over_the_plane() {
        let field = Field::on_plane(&FieldDesc {
            blades: 8192,
            ..FieldDesc::default()
        });
        let mut quadrants = [0; 4];
        for b in &field.blades {
            quadrants[(b.root().x > 0.0) as usize + 2 * (b.root().z > 0.0) as usize] += 1;
        }
        for q in quadrants {
            assert!((1948..=2148).contains(&q), "quadrant counts {quadrants:?}");
        }
    }
}
