#version 460
// The compute route (SPEC §10): the Bezier blades of the far distance buckets (from routes.x on,
// where the ordered list holds them last) are splatted by compute instead of drawn, one
// invocation per blade, into the splat target that splat.frag resolves into the frame. The near
// buckets are drawn as strips; the hand-over lies on a bucket boundary. Dispatched indirectly
// with the size order.wesl `order_buckets` wrote.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
#define SWARD_SPLAT_WRITE
#include "common.glsl"
#include "blade_surface.glsl"
#include "shading.glsl"
#include "splat.glsl"

layout(local_size_x_id = CONSTANT_WORKGROUP) in;

// Bounds on one blade's cells: far blades stay well inside them; a near blade splatted because
// the hand-over was set near the eye is cut short rather than stall the pass.
const int MAX_STEPS = 1024;
const int MAX_ACROSS = 64;

void main() {
    DrawCommand dispatch = draws[COMMAND_SPLAT_DISPATCH];
    uint i = dispatch.first_instance + gl_GlobalInvocationID.x;
    if (i >= draws[COMMAND_ALL].vertex_count) {
        return;
    }
    uint id = ordered[i];
    Blade b = blades[id];
    vec3 across = width_direction(b.up.xyz, b.v0.w);
    // A splatted blade is narrower than the drawn blades' least width (`blade_point` widens every
    // outline into its whole quad there): a flowering stalk is splatted as a leaf, its head
    // only in its colour (shade_blade).
    uint shape = blade_shape_code();
    splat_blade(SplatBlade(b.v0.xyz, b.v1.xyz, b.v2.xyz, across, b.v2.w, shape, blade_colour_key(id)), MAX_STEPS, MAX_ACROSS);
}
