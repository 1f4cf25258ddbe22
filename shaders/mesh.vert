// Vertices of lit meshes to world space: rigid target objects through u_model, or, with SKINNED
// defined, avatars through up to four joint matrices (model pose x inverse bind, already
// multiplied by the avatar's placement in the world) blended by the vertex's weights.
// Compiled by render/shader.cpp, which prepends #version 450 core and the defines.

layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;

#ifdef SKINNED
layout(location = 2) in uvec4 a_joints;
layout(location = 3) in vec4 a_weights;
layout(std140, binding = 0) uniform JointMatrices {
  mat4 u_joint[MAX_JOINTS];  // T_world_joint x inverse bind, per skeleton joint
};
#else
uniform mat4 u_model;
uniform mat3 u_normal_matrix;  // inverse transpose of u_model's 3 x 3 part
#endif

uniform mat4 u_view_projection;

out vec3 v_world_normal;

void main() {
#ifdef SKINNED
  mat4 skin = a_weights.x * u_joint[a_joints.x] + a_weights.y * u_joint[a_joints.y] +
              a_weights.z * u_joint[a_joints.z] + a_weights.w * u_joint[a_joints.w];
  vec4 world = skin * vec4(a_position, 1.0);
  // Joint matrices are rigid (rotation and translation), so their 3 x 3 part turns normals too.
  v_world_normal = mat3(skin) * a_normal;
#else
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world_normal = u_normal_matrix * a_normal;
#endif
  gl_Position = u_view_projection * world;
}
