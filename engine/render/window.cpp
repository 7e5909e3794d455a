#include "render/window.h"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <string>

#include "gpu/error.h"

namespace aeroflock::render {
namespace {

std::string last_glfw_error() {
  const char* description = nullptr;
  glfwGetError(&description);
  return description ? description : "unknown GLFW error";
}

Window* self(GLFWwindow* w) { return static_cast<Window*>(glfwGetWindowUserPointer(w)); }

}  // namespace

NoDisplay::NoDisplay(const std::string& detail)
    : std::runtime_error("aeroflock view needs a display (set DISPLAY or run under xvfb-run): " +
                         detail) {}

Window::Window(const std::string& title, int width, int height) {
  if (glfwInit() != GLFW_TRUE) throw NoDisplay(last_glfw_error());
  if (glfwVulkanSupported() != GLFW_TRUE) {
    glfwTerminate();
    throw NoDisplay("GLFW finds no Vulkan loader that can draw into a window");
  }
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    const std::string why = last_glfw_error();
    glfwTerminate();
    throw NoDisplay(why);
  }
  glfwSetWindowUserPointer(window_, this);
  glfwSetKeyCallback(window_, &Window::on_key);
  glfwSetScrollCallback(window_, &Window::on_scroll);
  glfwSetFramebufferSizeCallback(window_, &Window::on_resize);
  glfwGetCursorPos(window_, &cursor_x_, &cursor_y_);
}

Window::~Window() {
  glfwDestroyWindow(window_);
  glfwTerminate();
}

std::vector<const char*> Window::instance_extensions() const {
  uint32_t n = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&n);
  if (!names) throw NoDisplay("no Vulkan surface extensions for this window system");
  return {names, names + n};
}

VkSurfaceKHR Window::create_surface(VkInstance instance) const {
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  const VkResult r = glfwCreateWindowSurface(instance, window_, nullptr, &surface);
  if (r != VK_SUCCESS)
    throw NoDisplay(std::string("glfwCreateWindowSurface: ") + gpu::to_string(r) + " (" +
                    last_glfw_error() + ")");
  return surface;
}

VkExtent2D Window::framebuffer_size() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return {static_cast<uint32_t>(w), static_cast<uint32_t>(h)};
}

void Window::wait_while_minimised() const {
  for (VkExtent2D e = framebuffer_size(); (e.width == 0 || e.height == 0) && !should_close();
       e = framebuffer_size())
    glfwWaitEvents();
}

bool Window::should_close() const { return glfwWindowShouldClose(window_) == GLFW_TRUE; }
void Window::close() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
void Window::set_title(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }
bool Window::key_down(int key) const { return glfwGetKey(window_, key) == GLFW_PRESS; }

Input Window::poll() {
  glfwPollEvents();
  double x = 0.0, y = 0.0;
  glfwGetCursorPos(window_, &x, &y);
  if (glfwGetMouseButton(window_, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
    input_.drag_x += x - cursor_x_;
    input_.drag_y += y - cursor_y_;
  }
  cursor_x_ = x;
  cursor_y_ = y;
  Input out = std::move(input_);
  input_ = Input{};
  return out;
}

void Window::on_key(GLFWwindow* w, int key, int, int action, int mods) {
  if (action != GLFW_PRESS || key == GLFW_KEY_UNKNOWN) return;  // no auto-repeat
  self(w)->input_.pressed.push_back(key);
  self(w)->input_.mods.push_back(mods);
}

void Window::on_scroll(GLFWwindow* w, double, double y) { self(w)->input_.scroll += y; }

void Window::on_resize(GLFWwindow* w, int, int) { self(w)->input_.resized = true; }

}  // namespace aeroflock::render
