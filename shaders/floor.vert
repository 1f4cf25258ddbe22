// The floor: one square of half-size u_extent at height u_height, generated from gl_VertexID
// (six vertices, no vertex buffer).

uniform mat4 u_view_projection;
uniform float u_extent;
uniform float u_height;

out vec3 v_world_position;

const vec2 k_corners[6] =
    vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));

void main() {
  vec2 xz = u_extent * k_corners[gl_VertexID];
  v_world_position = vec3(xz.x, u_height, xz.y);
  gl_Position = u_view_projection * vec4(v_world_position, 1.0);
}
