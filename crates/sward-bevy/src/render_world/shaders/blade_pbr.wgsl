#define_import_path sward::blade_pbr

// A blade's fragment as Bevy's PBR takes it (the forward pass lights it, the deferred prepass
// writes it into the G-buffer): sward's look in Bevy's terms — its colours, rounded normals
// turned to the eye, root occlusion as diffuse occlusion, translucency as diffuse transmission.

#ifdef SWARD_PORTABLE
#import sward::portable_blades::{blade_albedo, blade_occlusion, blade_transmission}
#else
#import sward::blades::{blade_albedo, blade_occlusion, blade_transmission}
#endif
#import bevy_pbr::{
    pbr_types,
    mesh_types::{MESH_FLAGS_SHADOW_RECEIVER_BIT, MESH_FLAGS_TRANSMITTED_SHADOW_RECEIVER_BIT},
}

// The PBR input of the blade whose colour comes from `colour` at fragment `frag_coord`, `world_position`, with the
// blade's `normal` (either side's) and blade coordinates `uv`, seen from `eye`. `transmits`:
// the light through the blade from behind is Bevy's diffuse transmission (the forward pass);
// else (the G-buffer holds none) the diffuse colour keeps the share the forward pass leaves it
// and that light is lost.
fn blade_pbr_input(
    frag_coord: vec4<f32>,
    world_position: vec3<f32>,
    normal: vec3<f32>,
    uv: vec2<f32>,
    colour: vec3<u32>,
    eye: vec3<f32>,
    transmits: bool,
) -> pbr_types::PbrInput {
    let V = normalize(eye - world_position);
    // Two-sided: lit from the side the eye sees.
    var n = normalize(normal);
    n = select(-n, n, dot(n, V) >= 0.0);
    var pbr = pbr_types::pbr_input_new();
    let transmission = blade_transmission(uv.y);
    let albedo = blade_albedo(colour, uv.y, world_position);
    pbr.material.base_color = vec4(select(albedo * (1.0 - transmission), albedo, transmits), 1.0);
    pbr.material.diffuse_transmission = select(0.0, transmission, transmits);
    pbr.material.perceptual_roughness = 0.6;
    pbr.material.reflectance = vec3(0.25);
    pbr.material.flags = pbr_types::STANDARD_MATERIAL_FLAGS_FOG_ENABLED_BIT
        | pbr_types::STANDARD_MATERIAL_FLAGS_DOUBLE_SIDED_BIT;
    pbr.diffuse_occlusion = vec3(blade_occlusion(uv));
    pbr.frag_coord = frag_coord;
    pbr.world_position = vec4(world_position, 1.0);
    pbr.world_normal = n;
    pbr.N = n;
    pbr.V = V;
#ifdef GRASS_RECEIVES_SHADOWS
    pbr.flags = MESH_FLAGS_SHADOW_RECEIVER_BIT | MESH_FLAGS_TRANSMITTED_SHADOW_RECEIVER_BIT;
#endif
    return pbr;
}
