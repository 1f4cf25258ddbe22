// One directional light and a flat ambient term, white, so a surface's pixels keep its base
// colour's hue (the pixel tests rely on that) and only its brightness varies.

in vec3 v_world_normal;

uniform vec4 u_colour;           // linear RGBA
uniform vec3 u_light_direction;  // unit vector towards the light, world frame
uniform float u_ambient;         // share of the colour lit from everywhere

out vec4 o_colour;

void main() {
  vec3 n = normalize(v_world_normal);
  if (!gl_FrontFacing) {
    n = -n;  // thin screens and open meshes are lit from the side we see
  }
  float diffuse = max(dot(n, u_light_direction), 0.0);
  o_colour = vec4(u_colour.rgb * (u_ambient + (1.0 - u_ambient) * diffuse), u_colour.a);
}
