#pragma once
// The GLSL files of shaders/, embedded at build time (render/embed_shaders.cmake).

#include <string_view>

namespace deixis::render {

// The text of shaders/<name> (e.g. "mesh.vert"); throws deixis::Error for an unknown name.
std::string_view shader_source(std::string_view name);

}  // namespace deixis::render
