#pragma once
// The application's OpenGL context, as the session's graphics binding names it: EGL
// (XrGraphicsBindingEGLMNDX, XR_MNDX_egl_enable) or Xlib/GLX (XrGraphicsBindingOpenGLXlibKHR,
// XR_KHR_opengl_enable). Swapchain images are textures of that context.
//
// XR_KHR_opengl_enable lets the application leave its context unbound when it calls the runtime
// ("it may be bound in the thread calling those functions"), so the runtime binds it itself for
// its own GL work and puts back what was bound (BoundContext).
//
// The X11 and EGL headers stay in graphics_binding.cpp: Xlib's macros (Success, None, Status)
// break Eigen and the rest of the runtime.

#include <GL/gl.h>

#include <cstdint>
#include <string>

namespace deixis::xrt {

enum class GraphicsBinding : std::uint8_t { kNone, kEgl, kXlib };

// The GL functions the runtime calls, looked up through the platform (glXGetProcAddressARB,
// eglGetProcAddress) rather than linked by name: an application may define global symbols of
// the same names (hello_xr's GL loader has a function pointer variable `glTexStorage2D`), and the
// dynamic linker would bind the runtime's calls to those.
struct GlFunctions {
  void(APIENTRY* GenTextures)(GLsizei, GLuint*) = nullptr;
  void(APIENTRY* DeleteTextures)(GLsizei, const GLuint*) = nullptr;
  void(APIENTRY* BindTexture)(GLenum, GLuint) = nullptr;
  void(APIENTRY* TexStorage2D)(GLenum, GLsizei, GLenum, GLsizei, GLsizei) = nullptr;
  void(APIENTRY* GetTexImage)(GLenum, GLint, GLenum, GLenum, void*) = nullptr;
  void(APIENTRY* PixelStorei)(GLenum, GLint) = nullptr;
  GLenum(APIENTRY* GetError)() = nullptr;
};

struct SessionGraphics {
  GraphicsBinding binding = GraphicsBinding::kNone;
  GlFunctions gl;  // all set for an EGL or Xlib binding
  // EGL: display, context; Xlib: Display*, GLXContext, and the GLXDrawable as drawable.
  void* display = nullptr;
  void* context = nullptr;
  std::uint64_t drawable = 0;
};

// The graphics binding in an XrSessionCreateInfo's next chain. An EGL binding counts only when
// XR_MNDX_egl_enable is enabled (a structure of an extension not enabled is not one the runtime
// knows). Returns false with `problem` set when the binding is there but unusable (or a GL
// function cannot be found).
bool find_graphics_binding(const void* next, bool egl_enabled, SessionGraphics& out,
                           std::string& problem);

// Binds the session's context on this thread for the scope when it is not the current one, and
// binds back what was current after.
class BoundContext {
 public:
  explicit BoundContext(const SessionGraphics& graphics);
  ~BoundContext();
  BoundContext(const BoundContext&) = delete;
  BoundContext& operator=(const BoundContext&) = delete;
  bool ok() const { return ok_; }  // the session's context is current

 private:
  const SessionGraphics& graphics_;
  bool ok_ = false;
  bool switched_ = false;
  void* previous_display_ = nullptr;
  void* previous_context_ = nullptr;
  std::uint64_t previous_draw_ = 0;
  std::uint64_t previous_read_ = 0;
};

}  // namespace deixis::xrt
