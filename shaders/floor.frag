// A grid on the floor: lines every u_spacing metres, one pixel wide at any distance (fwidth),
// fading into the background with distance so the far floor does not shimmer.

in vec3 v_world_position;

uniform float u_spacing;
uniform vec3 u_camera_position;
uniform vec4 u_floor_colour;
uniform vec4 u_grid_colour;
uniform vec4 u_background;

out vec4 o_colour;

void main() {
  vec2 cell = v_world_position.xz / u_spacing;
  vec2 from_line = abs(fract(cell - 0.5) - 0.5) / max(fwidth(cell), vec2(1e-6));
  float line = 1.0 - min(min(from_line.x, from_line.y), 1.0);
  vec3 colour = mix(u_floor_colour.rgb, u_grid_colour.rgb, line);
  float haze = 1.0 - exp(-0.04 * distance(v_world_position, u_camera_position));
  o_colour = vec4(mix(colour, u_background.rgb, haze), 1.0);
}
