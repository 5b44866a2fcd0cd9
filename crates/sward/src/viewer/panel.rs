//! The viewer's egui panel: frame statistics, and every value of the scene file, edited live. The
//! panel edits a working copy; only a copy that passes the scene's own validation is applied, so
//! what runs is always what a scene file could hold.

use std::collections::VecDeque;

use egui::{CollapsingHeader, ComboBox, DragValue, Ui};
use glam::{Vec2, Vec3};
use sward_core::bodies::BodyShape;
use sward_core::instanced::Technique;
use sward_core::look::{BladeShadows, BladeShape, ShadingModel};
use sward_core::paint::{PaintNoise, TintNoise};
use sward_core::physics::{Collider, MAX_COLLIDERS};
use sward_core::quality::{DrawRoute, QualityPreset};
use sward_core::scene::Surface;
use sward_core::species::{SeedHeads, Species};
use sward_core::wind::{Wind, WindKind, MAX_WINDS};
use sward_core::{BladeOccluders, Scene};
use sward_gpu::timer::PassTimes;

use super::camera_control::Mode;

/// What the user asked for that the panel cannot do by editing the scene alone.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    ResetToRest,
    SingleStep,
    SaveScene(String),
    LoadScene(String),
    Screenshot,
    ResetCamera,
    ToggleCameraMode,
    /// Make the current view the scene's starting view.
    KeepView,
    /// Add the current view's eye to the camera path (for animations).
    AddPathPoint,
    /// Bake the paint into PNG maps beside the save path.
    SavePaintMaps,
}

/// Run-time switches that are not part of a scene.
#[derive(Clone, Debug)]
pub struct Controls {
    pub paused: bool,
    pub wireframe: bool,
    pub camera_mode: Mode,
    /// Samples per pixel the window renders with now.
    pub samples: u32,
}

/// Numbers the panel shows.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    pub fps: f32,
    pub cpu_ms: f32,
    pub gpu: Option<PassTimes>,
    pub blades_total: u32,
    pub blades_visible: Option<u32>,
    pub device: String,
    /// Recent CPU frame times in ms, oldest first.
    pub history: VecDeque<f32>,
    pub shader_status: Option<String>,
}

pub struct Panel {
    /// The working copy the widgets edit.
    pub edit: Scene,
    pub error: Option<String>,
    /// Something the user should know that is not an error (a route this GPU lacks fell back),
    /// shown until it is replaced.
    pub note: Option<String>,
    pub save_path: String,
    pub load_path: String,
    pub selected_collider: usize,
    pub wireframe_available: bool,
    /// Whether the trample map is shown (the viewer refreshes `trample_overlay` while it is).
    pub show_trample: bool,
    /// The trample map as last read back, seen from above.
    pub trample_overlay: Option<egui::TextureHandle>,
    /// The paint brush.
    pub brush: super::brush::Brush,
}

impl Panel {
    pub fn new(scene: &Scene, wireframe_available: bool) -> Self {
        Panel {
            edit: scene.clone(),
            error: None,
            note: None,
            save_path: format!("{}-saved.toml", scene.name),
            load_path: String::new(),
            selected_collider: 0,
            show_trample: false,
            trample_overlay: None,
            brush: super::brush::Brush::default(),
            wireframe_available,
        }
    }

    /// Draw the panel; returns the actions asked for. Applies the working copy to `scene` when it
    /// is valid.
    pub fn show(&mut self, ui: &mut Ui, scene: &mut Scene, controls: &mut Controls, stats: &Stats) -> Vec<Action> {
        let mut actions = Vec::new();
        egui::ScrollArea::vertical().show(ui, |ui| {
            show_stats(ui, stats);
            ui.separator();
            self.scene_file(ui, &mut actions);
            self.camera(ui, controls, &mut actions);
            self.field(ui);
            self.simulation(ui, controls, &mut actions);
            self.wind(ui);
            self.colliders(ui);
            self.culling(ui, controls);
            self.instanced(ui);
            self.billboards(ui);
            self.shading(ui);
            self.paint(ui, &mut actions);
            // Open where the scene has them, so what shapes its grass is in sight.
            let kinds = !self.edit.species.is_empty();
            CollapsingHeader::new("Kinds of grass")
                .default_open(kinds)
                .show(ui, |ui| species_editor(ui, &mut self.edit.species));
        });
        match self.edit.validate("panel") {
            Ok(()) => {
                self.error = None;
                if self.edit != *scene {
                    *scene = self.edit.clone();
                }
            }
            Err(e) => self.error = Some(e.to_string()),
        }
        actions
    }

    fn scene_file(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        if let Some(error) = &self.error {
            ui.colored_label(egui::Color32::from_rgb(255, 110, 90), error);
        }
        if let Some(note) = &self.note {
            ui.colored_label(egui::Color32::from_rgb(235, 200, 90), note);
        }
        ui.horizontal(|ui| {
            ui.label("scene");
            ui.text_edit_singleline(&mut self.edit.name);
        });
        ui.horizontal(|ui| {
            if ui.button("Save as").clicked() {
                actions.push(Action::SaveScene(self.save_path.clone()));
            }
            ui.text_edit_singleline(&mut self.save_path);
        });
        ui.horizontal(|ui| {
            if ui.button("Load").clicked() {
                actions.push(Action::LoadScene(self.load_path.clone()));
            }
            ui.text_edit_singleline(&mut self.load_path);
        });
        if ui.button("Screenshot (F12)").clicked() {
            actions.push(Action::Screenshot);
        }
    }

    fn camera(&mut self, ui: &mut Ui, controls: &Controls, actions: &mut Vec<Action>) {
        CollapsingHeader::new("Camera").show(ui, |ui| {
            ui.horizontal(|ui| {
                let label = match controls.camera_mode {
                    Mode::Orbit => "Orbit (Tab: fly)",
                    Mode::Fly => "Fly (Tab: walk)",
                    Mode::Walk => "Walk (Tab: orbit)",
                };
                if ui.button(label).clicked() {
                    actions.push(Action::ToggleCameraMode);
                }
                if ui.button("Reset (R)").clicked() {
                    actions.push(Action::ResetCamera);
                }
                if ui.button("Keep this view").clicked() {
                    actions.push(Action::KeepView);
                }
            });
            let cam = &mut self.edit.camera;
            number(ui, "field of view °", &mut cam.fov_y_degrees, 2.0..=170.0, 0.5);
            number(ui, "near", &mut cam.near, 0.001..=10.0, 0.01);
            number(ui, "far", &mut cam.far, 1.0..=10_000.0, 1.0);
            // The path `sward render --animation` moves the camera along.
            let path = &mut self.edit.camera_path;
            ui.horizontal(|ui| {
                ui.label(format!("path: {} points", path.points.len()));
                if ui.button("Add this view's eye").clicked() {
                    actions.push(Action::AddPathPoint);
                }
                if ui.button("Clear").clicked() {
                    path.points.clear();
                }
            });
            number(ui, "path speed", &mut path.speed, 0.0..=1000.0, 0.05);
            ui.checkbox(&mut path.dolly, "dolly (the target travels with the eye)");
            ui.checkbox(&mut path.above_ground, "above the ground (heights over the hills)");
        });
    }

    fn field(&mut self, ui: &mut Ui) {
        CollapsingHeader::new("Field").show(ui, |ui| {
            surface_editor(ui, &mut self.edit.surface);
            let f = &mut self.edit.field;
            ui.checkbox(&mut f.stream, "stream around the eye (blades: the budget)")
                .on_hover_text(
                    "a window of tiles of the instanced grass's grid follows the eye; plane, terrain and height map only",
                );
            ui.horizontal(|ui| {
                ui.label("blades");
                ui.add(
                    DragValue::new(&mut f.blades)
                        .range(1..=sward_core::scene::MAX_BLADES)
                        .speed(100.0),
                );
            });
            vec2(ui, "size", &mut f.size, 0.1..=10_000.0);
            range(ui, "height", &mut f.height, 0.01..=100.0);
            range(ui, "width", &mut f.width, 0.001..=10.0);
            range(ui, "stiffness", &mut f.stiffness, 0.1..=200.0);
            ui.horizontal(|ui| {
                ui.label("seed");
                ui.add(DragValue::new(&mut f.seed));
            });
        });
    }

    fn simulation(&mut self, ui: &mut Ui, controls: &mut Controls, actions: &mut Vec<Action>) {
        CollapsingHeader::new("Simulation").default_open(true).show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.checkbox(&mut controls.paused, "paused (Space)");
                if ui.button("Step").clicked() {
                    actions.push(Action::SingleStep);
                }
                if ui.button("Reset to rest").clicked() {
                    actions.push(Action::ResetToRest);
                }
            });
            let s = &mut self.edit.simulation;
            number(ui, "step s", &mut s.step, 0.0005..=0.05, 0.0005);
            ui.horizontal(|ui| {
                ui.label("max sub-steps");
                ui.add(DragValue::new(&mut s.max_substeps).range(1..=64));
            });
            ui.horizontal(|ui| {
                ui.checkbox(&mut s.forces.recovery, "recovery");
                ui.checkbox(&mut s.forces.gravity, "gravity");
                ui.checkbox(&mut s.forces.wind, "wind");
                ui.checkbox(&mut s.forces.collisions, "collisions");
            });
            vec3(ui, "gravity direction", &mut s.gravity_direction);
            number(ui, "gravity", &mut s.gravity_strength, 0.0..=100.0, 0.1);
            vec3(ui, "point gravity at", &mut s.point_gravity);
            number(ui, "point gravity", &mut s.point_gravity_strength, 0.0..=100.0, 0.1);
            number(ui, "point gravity blend", &mut s.point_gravity_blend, 0.0..=1.0, 0.01);
            number(ui, "η decay /s", &mut s.eta_decay, 0.0..=10.0, 0.01);
        });
    }

    fn wind(&mut self, ui: &mut Ui) {
        CollapsingHeader::new("Wind").default_open(true).show(ui, |ui| {
            let winds = &mut self.edit.wind;
            ui.horizontal(|ui| {
                if ui.button("Add field").clicked() && winds.len() < MAX_WINDS {
                    let last = *winds.last().expect("a scene has at least one wind field");
                    winds.push(last);
                }
                if ui.button("Remove last").clicked() && winds.len() > 1 {
                    winds.pop();
                }
            });
            let many = winds.len() > 1;
            for (i, w) in winds.iter_mut().enumerate() {
                ui.push_id(i, |ui| {
                    if many {
                        ui.label(format!("field {} (the fields are summed)", i + 1));
                    }
                    wind_field(ui, w);
                });
            }
        });
    }

    fn colliders(&mut self, ui: &mut Ui) {
        CollapsingHeader::new("Colliders").default_open(true).show(ui, |ui| {
            let colliders = &mut self.edit.colliders;
            ui.horizontal(|ui| {
                if ui.button("Add").clicked() && colliders.len() < MAX_COLLIDERS {
                    colliders.push(Collider::sphere(Vec3::new(0.0, 0.3, 0.0), 0.6));
                    self.selected_collider = colliders.len() - 1;
                }
                if ui.button("Remove").clicked() && self.selected_collider < colliders.len() {
                    colliders.remove(self.selected_collider);
                }
            });
            ui.label("Ctrl+drag in the view or arrow keys (PgUp/PgDn: height) move the selected one.");
            if let Some(selected) = colliders.get_mut(self.selected_collider) {
                ui.checkbox(&mut selected.cut, "selected one mows")
                    .on_hover_text("a cutter: it mows the grass under it to its underside, and the grass grows back");
                ui.checkbox(&mut selected.clear, "selected one clears the ground")
                    .on_hover_text("standing, no grass grows under it (collider.N.clear)");
            }
            for (i, collider) in colliders.iter_mut().enumerate() {
                ui.horizontal(|ui| {
                    ui.radio_value(&mut self.selected_collider, i, format!("#{i}"));
                    let before = collider.center;
                    xyz(ui, &mut collider.center);
                    // Editing the centre carries a travelling sphere's whole path along.
                    let moved = collider.center - before;
                    collider.path.iter_mut().for_each(|p| *p += moved);
                    ui.add(
                        DragValue::new(&mut collider.radius)
                            .speed(0.01)
                            .range(0.01..=100.0)
                            .prefix("r "),
                    );
                    if collider.path.len() >= 2 {
                        ui.add(
                            DragValue::new(&mut collider.speed)
                                .speed(0.05)
                                .range(0.0..=100.0)
                                .prefix("speed "),
                        );
                        ui.label(format!("{} path points", collider.path.len()));
                    }
                });
            }
            bodies(ui, &mut self.edit.bodies);
            trample(ui, &mut self.edit.trample);
            ui.checkbox(&mut self.show_trample, "show the map")
                .on_hover_text("the trample map from above: trails yellow, mown grass brown");
            if let (true, Some(overlay)) = (self.show_trample, &self.trample_overlay) {
                ui.image((overlay.id(), egui::vec2(128.0, 128.0)));
            }
        });
    }

    /// Which blades are drawn, and the instanced grass's settings.
    fn instanced(&mut self, ui: &mut Ui) {
        CollapsingHeader::new("Technique and instanced grass").show(ui, |ui| {
            let t = &mut self.edit.technique;
            ComboBox::from_label("technique")
                .selected_text(format!("{t:?}"))
                .show_ui(ui, |ui| {
                    for technique in [
                        Technique::Bezier,
                        Technique::Instanced,
                        Technique::Both,
                        Technique::Billboard,
                        Technique::Landscape,
                    ] {
                        ui.selectable_value(t, technique, format!("{technique:?}"));
                    }
                });
            let p = &mut self.edit.instanced;
            number(ui, "density /unit²", &mut p.grid.density, 1.0..=10_000.0, 1.0);
            number(ui, "cut-off radius", &mut p.grid.radius, 1.0..=5_000.0, 1.0);
            number(ui, "inner radius (both)", &mut p.grid.inner_radius, 0.0..=1_000.0, 0.1);
            number(ui, "LOD 1 from", &mut p.lod_distances[0], 0.1..=1_000.0, 0.1);
            number(ui, "LOD 2 from", &mut p.lod_distances[1], 0.1..=5_000.0, 0.5);
            number(ui, "LOD 3 from", &mut p.lod_distances[2], 0.1..=5_000.0, 0.5);
            number(ui, "splatted from", &mut p.splat_distance, 0.1..=5_000.0, 0.5);
            number(
                ui,
                "rasterized by compute from",
                &mut p.raster_distance,
                0.0..=1_000_000.0,
                0.5,
            );
            number(ui, "height min", &mut p.grid.height[0], 0.01..=10.0, 0.01);
            number(ui, "height max", &mut p.grid.height[1], 0.01..=10.0, 0.01);
            number(ui, "half-width min", &mut p.grid.width[0], 0.001..=1.0, 0.001);
            number(ui, "half-width max", &mut p.grid.width[1], 0.001..=1.0, 0.001);
            number(ui, "clump scale", &mut p.grid.clump_scale, 0.0..=10.0, 0.005);
            number(ui, "bend", &mut p.bend, 0.0..=2.0, 0.01);
            ui.add(DragValue::new(&mut p.grid.seed).prefix("seed "));
        });
    }

    /// The billboards' settings (techniques billboard and landscape).
    fn billboards(&mut self, ui: &mut Ui) {
        CollapsingHeader::new("Billboards").show(ui, |ui| {
            let p = &mut self.edit.billboard;
            number(ui, "density /unit²", &mut p.grid.density, 0.01..=1_000.0, 0.05);
            number(ui, "cut-off radius", &mut p.grid.radius, 1.0..=10_000.0, 1.0);
            number(
                ui,
                "inner radius (landscape)",
                &mut p.grid.inner_radius,
                0.0..=5_000.0,
                0.5,
            );
            number(ui, "fade-in band", &mut p.fade, 0.0..=500.0, 0.5);
            number(ui, "height min", &mut p.grid.height[0], 0.01..=10.0, 0.01);
            number(ui, "height max", &mut p.grid.height[1], 0.01..=10.0, 0.01);
            number(ui, "half-width min", &mut p.grid.width[0], 0.01..=5.0, 0.01);
            number(ui, "half-width max", &mut p.grid.width[1], 0.01..=5.0, 0.01);
            number(ui, "clump scale", &mut p.grid.clump_scale, 0.0..=10.0, 0.005);
            number(ui, "sway", &mut p.grid.sway, 0.0..=2.0, 0.01);
            number(ui, "one quad beyond", &mut p.one_quad_distance, 0.0..=1_000_000.0, 1.0);
            number(ui, "splatted beyond", &mut p.splat_distance, 0.0..=1_000_000.0, 1.0);
            number(ui, "computed from", &mut p.raster_distance, 0.0..=1_000_000.0, 1.0);
            ui.checkbox(&mut p.depth_prepass, "depth pre-pass")
                .on_hover_text("shade only the nearest billboard at each sample: same picture, less fill");
            ui.add(DragValue::new(&mut p.grid.seed).prefix("seed "));
        });
    }

    fn culling(&mut self, ui: &mut Ui, controls: &mut Controls) {
        CollapsingHeader::new("Culling and detail").show(ui, |ui| {
            let c = &mut self.edit.cull;
            ui.checkbox(&mut c.orientation, "orientation");
            number(ui, "  threshold", &mut c.orientation_threshold, 0.01..=1.0, 0.005);
            ui.checkbox(&mut c.frustum, "view frustum");
            number(ui, "  tolerance", &mut c.frustum_tolerance, 0.0..=10.0, 0.01);
            ui.checkbox(&mut c.distance, "distance");
            ui.horizontal(|ui| {
                ui.label("  levels n");
                ui.add(DragValue::new(&mut c.distance_levels).range(1..=1000));
            });
            number(ui, "  d_max", &mut c.distance_max, 0.1..=10_000.0, 0.5);
            ui.checkbox(&mut c.tiles, "tiles");
            number(ui, "  simulated margin", &mut c.tile_margin, 0.0..=100.0, 0.1);
            ui.checkbox(&mut c.occlusion, "occlusion (Hi-Z)");
            number(ui, "  depth tolerance", &mut c.occlusion_tolerance, 0.0..=100.0, 0.05);
            blade_occluders(ui, &mut c.blade_occluders);
            let l = &mut self.edit.lod;
            number(ui, "LOD min level", &mut l.min_level, 1.0..=64.0, 0.1);
            number(ui, "LOD max level", &mut l.max_level, 1.0..=64.0, 0.1);
            number(ui, "LOD near", &mut l.near, 0.0..=1000.0, 0.1);
            number(ui, "LOD far", &mut l.far, 0.01..=1000.0, 0.1);
            let b = &mut self.edit.blades;
            ComboBox::from_label("blade shape")
                .selected_text(format!("{:?}", b.shape))
                .show_ui(ui, |ui| {
                    for shape in [
                        BladeShape::Quad,
                        BladeShape::Triangle,
                        BladeShape::Quadratic,
                        BladeShape::TriangleTip,
                    ] {
                        ui.selectable_value(&mut b.shape, shape, format!("{shape:?}"));
                    }
                });
            number(ui, "tip threshold", &mut b.tip_threshold, 0.0..=0.99, 0.01);
            ui.checkbox(&mut b.ridge, "3D ridge");
            number(ui, "min width px (0: off)", &mut b.min_width_pixels, 0.0..=16.0, 0.05);
            ui.add_enabled(
                self.wireframe_available,
                egui::Checkbox::new(&mut controls.wireframe, "wireframe"),
            );
            let route = &mut self.edit.quality.route;
            ComboBox::from_label("draw route")
                .selected_text(route.name())
                .show_ui(ui, |ui| {
                    for r in DrawRoute::ALL {
                        ui.selectable_value(route, r, r.name());
                    }
                });
            ui.checkbox(&mut self.edit.lod.compute_raster, "compute rasterizer (compute route)");
            number(
                ui,
                "rasterized by compute from",
                &mut self.edit.lod.strip_distance,
                0.0..=1000.0,
                0.5,
            );
            number(
                ui,
                "splat from (compute route)",
                &mut self.edit.lod.splat_distance,
                0.0..=1000.0,
                0.5,
            );
            let q = &mut self.edit.quality.preset;
            ComboBox::from_label("quality")
                .selected_text(q.name())
                .show_ui(ui, |ui| {
                    for preset in QualityPreset::ALL {
                        ui.selectable_value(q, preset, preset.name());
                    }
                });
            ui.label(format!(
                "{}× MSAA (a new preset's samples and shadow map regrow the field)",
                controls.samples
            ));
        });
    }

    fn shading(&mut self, ui: &mut Ui) {
        CollapsingHeader::new("Shading").show(ui, |ui| {
            let s = &mut self.edit.shading;
            vec3(ui, "light direction", &mut s.light_direction);
            color(ui, "light colour", &mut s.light_color);
            number(ui, "ambient", &mut s.ambient, 0.0..=1.0, 0.01);
            color(ui, "root colour", &mut s.root_color);
            color(ui, "tip colour", &mut s.tip_color);
            number(ui, "colour jitter", &mut s.color_jitter, 0.0..=1.0, 0.01);
            color(ui, "ground", &mut s.ground_color);
            number(ui, "ground water", &mut s.ground_water, 0.0..=1.0, 0.01);
            color(ui, "sky zenith", &mut s.sky_zenith);
            color(ui, "sky horizon", &mut s.sky_horizon);
            number(ui, "fog density", &mut s.fog_density, 0.0..=1.0, 0.0005);
            ComboBox::from_label("shading model")
                .selected_text(format!("{:?}", s.model))
                .show_ui(ui, |ui| {
                    for model in [ShadingModel::Lambert, ShadingModel::BlinnPhong] {
                        ui.selectable_value(&mut s.model, model, format!("{model:?}"));
                    }
                });
            number(ui, "  tip specular", &mut s.specular, 0.0..=4.0, 0.01);
            number(ui, "  shininess", &mut s.shininess, 1.0..=256.0, 0.5);
            number(ui, "translucency", &mut s.translucency, 0.0..=4.0, 0.01);
            number(ui, "ambient occlusion", &mut s.ambient_occlusion, 0.0..=1.0, 0.01);
            number(ui, "clump variation", &mut s.clump_variation, 0.0..=1.0, 0.01);
            number(ui, "clump scale", &mut s.clump_scale, 0.001..=10.0, 0.005);
            ui.checkbox(&mut s.shadows, "sun shadows");
            ComboBox::from_label("  blade shadows")
                .selected_text(s.blade_shadows.name())
                .show_ui(ui, |ui| {
                    for choice in BladeShadows::ALL {
                        ui.selectable_value(&mut s.blade_shadows, choice, choice.name());
                    }
                });
            number(
                ui,
                "  blade shadow reach",
                &mut s.blade_shadow_distance,
                0.0..=1000.0,
                0.1,
            );
        });
    }
}

/// What the grass grows on: plane, sphere, terrain or a mesh file, each with its parameters.
impl Panel {
    /// The brush: what it paints, how much, how wide; saving its maps.
    fn paint(&mut self, ui: &mut Ui, actions: &mut Vec<Action>) {
        use super::brush::Painting;
        CollapsingHeader::new("Paint")
            .default_open(self.edit.paint.paints())
            .show(ui, |ui| {
                let brush = &mut self.brush;
                ui.checkbox(&mut brush.on, "brush (left drag paints the ground)");
                let name = |p: Painting, scene: &Scene| match p {
                    Painting::Density => "density".to_string(),
                    Painting::Length => "length".to_string(),
                    Painting::Species(k) => {
                        format!("species {}", scene.species.get(k).map_or("?", |s| s.name.as_str()))
                    }
                };
                ComboBox::from_label("paints")
                    .selected_text(name(brush.painting, &self.edit))
                    .show_ui(ui, |ui| {
                        let kinds = (0..self.edit.species.len()).map(Painting::Species);
                        for p in [Painting::Density, Painting::Length].into_iter().chain(kinds) {
                            ui.selectable_value(&mut brush.painting, p, name(p, &self.edit));
                        }
                    });
                if !matches!(brush.painting, Painting::Species(_)) {
                    number(ui, "to", &mut brush.value, 0.0..=1.0, 0.01);
                }
                number(ui, "radius", &mut brush.radius, 0.1..=50.0, 0.05);
                number(ui, "falloff (share of the radius)", &mut brush.falloff, 0.0..=1.0, 0.01);
                number(ui, "strength", &mut brush.strength, 0.0..=1.0, 0.01);
                ui.separator();
                patches(ui, "bare patches (paint.noise)", &mut self.edit.paint.noise, None);
                let tint = &mut self.edit.paint.tint_noise;
                let mut as_patches = tint.map(|t| PaintNoise {
                    scale: t.scale,
                    cover: t.cover,
                    softness: t.softness,
                });
                let mut color = tint.map_or(TintNoise::default().color, |t| t.color);
                patches(
                    ui,
                    "tinted patches (paint.tint_noise)",
                    &mut as_patches,
                    Some(&mut color),
                );
                *tint = as_patches.map(|p| TintNoise {
                    scale: p.scale,
                    cover: p.cover,
                    softness: p.softness,
                    color,
                });
                let [x0, z0, x1, z1] = self.edit.paint.area;
                ui.label(format!("paints within x {x0}..{x1}, z {z0}..{z1} ([paint] area)"));
                if ui.button("Save maps (PNG, beside the save path)").clicked() {
                    actions.push(Action::SavePaintMaps);
                }
            });
    }
}

/// A noise's patches, on or off (`None`), with their scale, cover and softness, and the tinted
/// patches' colour where there is one.
fn patches(ui: &mut Ui, label: &str, noise: &mut Option<PaintNoise>, color: Option<&mut Vec3>) {
    let mut on = noise.is_some();
    ui.checkbox(&mut on, label);
    match (on, noise.as_mut()) {
        (false, _) => *noise = None,
        (true, None) => *noise = Some(PaintNoise::default()),
        (true, Some(n)) => {
            number(ui, "  patches per unit", &mut n.scale, 0.001..=1.0, 0.001);
            number(ui, "  cover", &mut n.cover, 0.0..=1.0, 0.01);
            number(ui, "  softness", &mut n.softness, 0.0..=0.5, 0.01);
            if let Some(c) = color {
                vec3(ui, "  colour ×", c);
            }
        }
    }
}

/// The kinds of grass (`[[species]]`): each one's weight, shape, stiffness and colours; adding
/// one (as the meadow's grass, renamed) and removing the last.
fn species_editor(ui: &mut Ui, species: &mut Vec<Species>) {
    for s in species.iter_mut() {
        ui.label(format!(
            "{}{}",
            s.name,
            if s.painted_only { " (only where painted)" } else { "" }
        ));
        number(ui, "  weight", &mut s.weight, 0.0..=100.0, 0.01);
        range(ui, "  height", &mut s.height, 0.01..=10.0);
        range(ui, "  half-width", &mut s.width, 0.001..=1.0);
        range(ui, "  stiffness", &mut s.stiffness, 0.1..=100.0);
        number(ui, "  bend", &mut s.bend, 0.0..=1.0, 0.01);
        color(ui, "  root", &mut s.root_color);
        color(ui, "  tip", &mut s.tip_color);
        seed_heads_editor(ui, &mut s.seed_heads);
    }
    ui.horizontal(|ui| {
        if species.len() < sward_core::species::MAX_SPECIES && ui.button("Add a kind").clicked() {
            species.push(Species {
                name: format!("kind {}", species.len() + 1),
                ..Species::default()
            });
        }
        if !species.is_empty() && ui.button("Remove the last").clicked() {
            species.pop();
        }
    });
}

/// A species' flowering stalks: on or off, their share, head length and colour.
fn seed_heads_editor(ui: &mut Ui, heads: &mut Option<SeedHeads>) {
    let mut on = heads.is_some();
    ui.checkbox(&mut on, "  seed heads");
    match (on, heads.as_mut()) {
        (false, _) => *heads = None,
        (true, None) => *heads = Some(SeedHeads::default()),
        (true, Some(h)) => {
            number(ui, "    share of blades", &mut h.share, 0.0..=1.0, 0.01);
            number(ui, "    head length", &mut h.length, 0.05..=0.6, 0.01);
            color(ui, "    head", &mut h.color);
        }
    }
}

fn surface_editor(ui: &mut Ui, surface: &mut Surface) {
    let name = |s: &Surface| match s {
        Surface::Plane => "plane",
        Surface::Sphere { .. } => "sphere",
        Surface::Terrain { .. } => "terrain",
        Surface::Mesh { .. } => "mesh (OBJ, glTF)",
        Surface::Heightmap { .. } => "height map (PNG)",
    };
    let choices = [
        Surface::Plane,
        Surface::Sphere {
            center: Vec3::ZERO,
            radius: 6.0,
        },
        Surface::Terrain {
            size: Vec2::splat(40.0),
            height: 3.0,
            resolution: 128,
            seed: 1,
        },
        Surface::Mesh {
            path: "ground.obj".into(),
            scale: 1.0,
        },
        Surface::Heightmap {
            path: "heights.png".into(),
            size: Vec2::splat(40.0),
            height: 4.0,
        },
    ];
    ComboBox::from_label("surface")
        .selected_text(name(surface))
        .show_ui(ui, |ui| {
            for choice in choices {
                let label = name(&choice);
                if ui.selectable_label(name(surface) == label, label).clicked() && name(surface) != label {
                    *surface = choice;
                }
            }
        });
    match surface {
        Surface::Plane => {}
        Surface::Sphere { center, radius } => {
            vec3(ui, "centre", center);
            number(ui, "radius", radius, 0.1..=10_000.0, 0.05);
        }
        Surface::Terrain {
            size,
            height,
            resolution,
            seed,
        } => {
            vec2(ui, "size", size, 0.1..=10_000.0);
            number(ui, "hill height", height, 0.0..=1000.0, 0.05);
            ui.horizontal(|ui| {
                ui.label("resolution");
                ui.add(DragValue::new(resolution).range(2..=2048));
                ui.label("seed");
                ui.add(DragValue::new(seed));
            });
        }
        Surface::Heightmap { path, size, height } => {
            ui.horizontal(|ui| {
                ui.label("PNG file");
                ui.text_edit_singleline(path);
            });
            vec2(ui, "size", size, 0.1..=100_000.0);
            number(ui, "height", height, 0.0..=10_000.0, 0.05);
        }
        Surface::Mesh { path, scale } => {
            ui.horizontal(|ui| {
                ui.label("OBJ or glTF file");
                ui.text_edit_singleline(path);
            });
            number(ui, "scale", scale, 0.0001..=10_000.0, 0.01);
        }
    }
}

fn show_stats(ui: &mut Ui, stats: &Stats) {
    ui.label(&stats.device);
    ui.label(format!("{:.0} FPS   CPU {:.2} ms", stats.fps, stats.cpu_ms));
    match stats.gpu {
        Some(t) => ui.label(format!(
            "GPU {:.2} ms: occluders {:.2}, trample {:.2}, simulate {:.2}, cull {:.2}, blade shadows {:.2}, draw {:.2}, UI {:.2}",
            t.total(),
            t.occluders,
            t.trample,
            t.simulate,
            t.cull,
            t.shadows,
            t.draw,
            t.ui
        )),
        None => ui.label("GPU times: waiting for the first frame"),
    };
    let visible = stats.blades_visible.map_or("…".to_string(), |v| v.to_string());
    ui.label(format!(
        "blades {} total, {} after culling",
        stats.blades_total, visible
    ));
    if let Some(status) = &stats.shader_status {
        ui.colored_label(egui::Color32::from_rgb(255, 200, 90), status);
    }
    frame_time_graph(ui, &stats.history);
}

/// CPU frame times as a line, scaled to the slowest recent frame.
fn frame_time_graph(ui: &mut Ui, history: &VecDeque<f32>) {
    let size = egui::vec2(ui.available_width().min(320.0), 48.0);
    let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, egui::Color32::from_gray(24));
    let peak = history.iter().copied().fold(1.0f32, f32::max);
    let n = history.len().max(2) as f32 - 1.0;
    let points: Vec<egui::Pos2> = history
        .iter()
        .enumerate()
        .map(|(i, ms)| {
            egui::pos2(
                rect.left() + rect.width() * i as f32 / n,
                rect.bottom() - rect.height() * ms / peak,
            )
        })
        .collect();
    painter.add(egui::Shape::line(
        points,
        egui::Stroke::new(1.0, egui::Color32::from_rgb(120, 220, 120)),
    ));
    painter.text(
        rect.left_top(),
        egui::Align2::LEFT_TOP,
        format!("{peak:.1} ms"),
        egui::FontId::monospace(10.0),
        egui::Color32::GRAY,
    );
}

fn number(ui: &mut Ui, label: &str, value: &mut f32, bounds: std::ops::RangeInclusive<f32>, speed: f64) {
    ui.horizontal(|ui| {
        ui.label(label);
        ui.add(DragValue::new(value).speed(speed).range(bounds).max_decimals(4));
    });
}

fn range(ui: &mut Ui, label: &str, value: &mut [f32; 2], bounds: std::ops::RangeInclusive<f32>) {
    ui.horizontal(|ui| {
        ui.label(label);
        ui.add(
            DragValue::new(&mut value[0])
                .speed(0.005)
                .range(bounds.clone())
                .max_decimals(4),
        );
        ui.label("to");
        ui.add(DragValue::new(&mut value[1]).speed(0.005).range(bounds).max_decimals(4));
    });
}

fn vec2(ui: &mut Ui, label: &str, value: &mut Vec2, bounds: std::ops::RangeInclusive<f32>) {
    ui.horizontal(|ui| {
        ui.label(label);
        ui.add(DragValue::new(&mut value.x).speed(0.1).range(bounds.clone()));
        ui.add(DragValue::new(&mut value.y).speed(0.1).range(bounds));
    });
}

fn xyz(ui: &mut Ui, value: &mut Vec3) {
    ui.add(DragValue::new(&mut value.x).speed(0.02).prefix("x "));
    ui.add(DragValue::new(&mut value.y).speed(0.02).prefix("y "));
    ui.add(DragValue::new(&mut value.z).speed(0.02).prefix("z "));
}

fn vec3(ui: &mut Ui, label: &str, value: &mut Vec3) {
    ui.horizontal(|ui| {
        ui.label(label);
        xyz(ui, value);
    });
}

fn color(ui: &mut Ui, label: &str, value: &mut Vec3) {
    ui.horizontal(|ui| {
        let mut rgb = value.to_array();
        ui.color_edit_button_rgb(&mut rgb);
        ui.label(label);
        *value = Vec3::from_array(rgb);
    });
}

/// The editors of one wind field.
fn wind_field(ui: &mut Ui, w: &mut Wind) {
    ComboBox::from_label("wind field")
        .selected_text(format!("{:?}", w.kind))
        .show_ui(ui, |ui| {
            for kind in WindKind::ALL {
                ui.selectable_value(&mut w.kind, kind, format!("{kind:?}"));
            }
        });
    vec3(ui, "direction", &mut w.direction);
    number(ui, "strength", &mut w.strength, 0.0..=100.0, 0.1);
    number(ui, "gust", &mut w.gust, 0.0..=1.0, 0.01);
    number(ui, "gust frequency", &mut w.gust_frequency, 0.0..=20.0, 0.05);
    number(ui, "noise scale", &mut w.scale, 0.001..=10.0, 0.005);
    number(ui, "noise speed", &mut w.speed, 0.0..=100.0, 0.1);
    vec3(ui, "centre", &mut w.center);
}

/// The mesh colliders: how many spheres pack each, where it is, how fast it travels, whether it rolls.
fn bodies(ui: &mut Ui, bodies: &mut [sward_core::bodies::Body]) {
    if !bodies.is_empty() {
        ui.label("Bodies (meshes packed into spheres):");
    }
    for (i, body) in bodies.iter_mut().enumerate() {
        ui.horizontal(|ui| {
            ui.label(format!("body {i}"));
            let before = body.center;
            xyz(ui, &mut body.center);
            let moved = body.center - before;
            body.path.iter_mut().for_each(|p| *p += moved);
            ui.add(DragValue::new(&mut body.spheres).range(1..=64).prefix("spheres "));
            ui.add(
                DragValue::new(&mut body.speed)
                    .speed(0.05)
                    .range(0.0..=100.0)
                    .prefix("speed "),
            );
            ui.checkbox(&mut body.roll, "roll");
            ui.checkbox(&mut body.clear, "clears the ground");
            match &mut body.shape {
                BodyShape::Boulder { radius, seed } => {
                    ui.add(
                        DragValue::new(radius)
                            .speed(0.01)
                            .range(0.05..=100.0)
                            .prefix("boulder r "),
                    );
                    ui.add(DragValue::new(seed).prefix("seed "));
                }
                BodyShape::Mesh { path, scale } => {
                    ui.label(path.as_str());
                    ui.add(DragValue::new(scale).speed(0.01).range(0.001..=1000.0).prefix("scale "));
                }
            }
        });
    }
}

/// The panel row of `cull.blade_occluders`: `auto` (follows the field's density) or a count.
fn blade_occluders(ui: &mut Ui, occluders: &mut BladeOccluders) {
    ui.horizontal(|ui| {
        ui.label("  nearest blades occlude").on_hover_text(
            "auto: as many as the field's density asks; 0: only the ground and the colliders hide blades",
        );
        let mut auto = *occluders == BladeOccluders::Auto;
        if ui.checkbox(&mut auto, "auto").changed() {
            *occluders = if auto {
                BladeOccluders::Auto
            } else {
                BladeOccluders::Count(BladeOccluders::AUTO_FLOOR)
            };
        }
        if let BladeOccluders::Count(n) = occluders {
            ui.add(DragValue::new(n).range(0..=1 << 20));
        }
    });
}

/// The trample map's rows: whether colliders flatten the generated grass, over how much ground,
/// and how fast mown grass grows back.
fn trample(ui: &mut Ui, t: &mut sward_core::trample::TrampleParams) {
    ui.checkbox(&mut t.enabled, "trample map")
        .on_hover_text("colliders flatten the instanced blades and billboards; trails fade as blades recover");
    ui.horizontal(|ui| {
        ui.add(
            DragValue::new(&mut t.extent)
                .speed(1.0)
                .range(1.0..=100_000.0)
                .suffix(" u"),
        )
        .on_hover_text("units of ground the map covers around the eye");
        ui.add(DragValue::new(&mut t.resolution).range(16..=4096).suffix("²"))
            .on_hover_text("texels along each side of the map");
        ui.add(
            DragValue::new(&mut t.regrow)
                .speed(0.01)
                .range(0.0..=100.0)
                .suffix(" u/s"),
        )
        .on_hover_text("how fast mown grass grows back");
    });
}
