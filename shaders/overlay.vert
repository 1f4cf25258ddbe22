// Unlit coloured geometry: debug lines in world space (u_model = identity) and labels in label
// space (u_model places the label as a billboard above its object).

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_colour;

uniform mat4 u_view_projection;
uniform mat4 u_model;

out vec4 v_colour;

void main() {
  v_colour = a_colour;
  gl_Position = u_view_projection * (u_model * vec4(a_position, 1.0));
}
