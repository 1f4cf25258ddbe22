// Swapchains: GL textures of the application's context (an OpenGL session, EGL or Xlib/GLX; a
// headless session offers no formats), and the acquire → wait → release order per image.

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>

#include "xr_test_runtime/api.h"

namespace deixis::xrt {

namespace {

const int64_t kFormats[] = {GL_SRGB8_ALPHA8, GL_RGBA8, GL_DEPTH_COMPONENT32F};

bool valid_session(const Runtime& rt, XrSession session) {
  return rt.instance_live && rt.session != 0 && from_handle(session) == rt.session;
}

}  // namespace

XrResult XRAPI_CALL EnumerateSwapchainFormats(XrSession session, uint32_t capacity, uint32_t* count,
                                              int64_t* formats) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (count == nullptr) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  const uint32_t n = rt.session_state.headless ? 0 : 3;
  *count = n;
  if (capacity == 0) {
    return XR_SUCCESS;
  }
  if (capacity < n || formats == nullptr) {
    return XR_ERROR_SIZE_INSUFFICIENT;
  }
  std::copy(kFormats, kFormats + n, formats);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL CreateSwapchain(XrSession session, const XrSwapchainCreateInfo* info,
                                    XrSwapchain* swapchain) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  if (!valid_session(rt, session)) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || swapchain == nullptr || info->type != XR_TYPE_SWAPCHAIN_CREATE_INFO ||
      info->width == 0 || info->height == 0 || info->width > 2048 || info->height > 2048 ||
      info->arraySize != 1 || info->mipCount != 1 || info->faceCount != 1 ||
      info->sampleCount != 1) {
    return rt.refuse("xrCreateSwapchain", XR_ERROR_VALIDATION_FAILURE);
  }
  if (rt.session_state.headless ||
      std::find(std::begin(kFormats), std::end(kFormats), info->format) == std::end(kFormats)) {
    return rt.refuse("xrCreateSwapchain", XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED);
  }
  // The images are textures of the application's context, made with it bound.
  const BoundContext bound(rt.session_state.graphics);
  if (!bound.ok()) {
    return rt.refuse("xrCreateSwapchain", XR_ERROR_RUNTIME_FAILURE);  // cannot bind it
  }
  SwapchainObject s;
  s.width = info->width;
  s.height = info->height;
  s.format = info->format;
  s.textures.resize(s.image_count);
  const GlFunctions& gl = rt.session_state.graphics.gl;
  while (gl.GetError() != GL_NO_ERROR) {
    // errors the application left: not ours to report
  }
  gl.GenTextures(static_cast<GLsizei>(s.image_count), s.textures.data());
  for (GLuint t : s.textures) {
    gl.BindTexture(GL_TEXTURE_2D, t);
    gl.TexStorage2D(GL_TEXTURE_2D, 1, static_cast<GLenum>(info->format),
                    static_cast<GLsizei>(info->width), static_cast<GLsizei>(info->height));
  }
  gl.BindTexture(GL_TEXTURE_2D, 0);
  if (gl.GetError() != GL_NO_ERROR) {
    gl.DeleteTextures(static_cast<GLsizei>(s.image_count), s.textures.data());
    return rt.refuse("xrCreateSwapchain", XR_ERROR_RUNTIME_FAILURE);  // no current GL context?
  }
  const std::uint64_t id = rt.new_handle();
  rt.swapchains[id] = std::move(s);
  *swapchain = to_handle<XrSwapchain>(id);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL DestroySwapchain(XrSwapchain swapchain) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const auto it = rt.swapchains.find(from_handle(swapchain));
  if (it == rt.swapchains.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (const BoundContext bound(rt.session_state.graphics); bound.ok()) {
    rt.session_state.graphics.gl.DeleteTextures(static_cast<GLsizei>(it->second.textures.size()),
                                                it->second.textures.data());
  }
  rt.swapchains.erase(it);
  return XR_SUCCESS;
}

XrResult XRAPI_CALL EnumerateSwapchainImages(XrSwapchain swapchain, uint32_t capacity,
                                             uint32_t* count, XrSwapchainImageBaseHeader* images) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const auto it = rt.swapchains.find(from_handle(swapchain));
  if (it == rt.swapchains.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (count == nullptr) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  const SwapchainObject& s = it->second;
  *count = s.image_count;
  if (capacity == 0) {
    return XR_SUCCESS;
  }
  if (capacity < s.image_count || images == nullptr) {
    return XR_ERROR_SIZE_INSUFFICIENT;
  }
  auto* gl = reinterpret_cast<XrSwapchainImageOpenGLKHR*>(images);
  for (uint32_t i = 0; i < s.image_count; ++i) {
    if (gl[i].type != XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR) {
      return XR_ERROR_VALIDATION_FAILURE;
    }
    gl[i].image = s.textures[i];
  }
  return XR_SUCCESS;
}

XrResult XRAPI_CALL AcquireSwapchainImage(XrSwapchain swapchain,
                                          const XrSwapchainImageAcquireInfo* info,
                                          uint32_t* index) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const auto it = rt.swapchains.find(from_handle(swapchain));
  if (it == rt.swapchains.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (index == nullptr || (info != nullptr && info->type != XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO)) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  SwapchainObject& s = it->second;
  if (s.acquired.size() == s.image_count) {
    return rt.refuse("xrAcquireSwapchainImage", XR_ERROR_CALL_ORDER_INVALID);
  }
  *index = s.next;
  s.acquired.push_back(s.next);
  s.next = (s.next + 1) % s.image_count;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL WaitSwapchainImage(XrSwapchain swapchain,
                                       const XrSwapchainImageWaitInfo* info) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const auto it = rt.swapchains.find(from_handle(swapchain));
  if (it == rt.swapchains.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info == nullptr || info->type != XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  SwapchainObject& s = it->second;
  if (s.acquired.empty() || s.waited) {
    return rt.refuse("xrWaitSwapchainImage", XR_ERROR_CALL_ORDER_INVALID);
  }
  s.waited = true;
  return XR_SUCCESS;
}

XrResult XRAPI_CALL ReleaseSwapchainImage(XrSwapchain swapchain,
                                          const XrSwapchainImageReleaseInfo* info) {
  Runtime& rt = state();
  std::lock_guard lock(rt.mutex);
  const auto it = rt.swapchains.find(from_handle(swapchain));
  if (it == rt.swapchains.end()) {
    return XR_ERROR_HANDLE_INVALID;
  }
  if (info != nullptr && info->type != XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO) {
    return XR_ERROR_VALIDATION_FAILURE;
  }
  SwapchainObject& s = it->second;
  if (s.acquired.empty() || !s.waited) {
    return rt.refuse("xrReleaseSwapchainImage", XR_ERROR_CALL_ORDER_INVALID);
  }
  s.last_released = s.acquired.front();
  s.acquired.pop_front();
  s.waited = false;
  return XR_SUCCESS;
}

}  // namespace deixis::xrt
