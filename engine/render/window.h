// A GLFW window for Vulkan (no OpenGL context) and what the user did with the mouse and keys.
#pragma once

#include <vulkan/vulkan.h>

#include <stdexcept>
#include <string>
#include <vector>

struct GLFWwindow;

namespace aeroflock::render {

// No display to open a window on (no DISPLAY, no X server) or no Vulkan surface for it.
struct NoDisplay : std::runtime_error {
  explicit NoDisplay(const std::string& detail);
};

// What happened since the last poll.
struct Input {
  std::vector<int> pressed;  // keys pressed, GLFW_KEY_*, in order (not auto-repeats)
  std::vector<int> mods;     // GLFW_MOD_* of each of `pressed`
  double drag_x = 0.0;       // cursor movement with the left button held, pixels
  double drag_y = 0.0;
  double scroll = 0.0;   // wheel clicks, away from the user > 0
  bool resized = false;  // the framebuffer changed size
};

class Window {
 public:
  // Initialises GLFW (once per process) and opens the window; throws NoDisplay.
  Window(const std::string& title, int width, int height);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // The instance extensions the window's surface needs.
  std::vector<const char*> instance_extensions() const;
  // The window's surface on `instance` (the caller owns it); throws NoDisplay.
  VkSurfaceKHR create_surface(VkInstance instance) const;

  VkExtent2D framebuffer_size() const;
  // Blocks while the window is minimised (a zero framebuffer), unless it is closing.
  void wait_while_minimised() const;
  bool should_close() const;
  void close();
  void set_title(const std::string& title);
  bool key_down(int key) const;

  // Processes the window system's events; returns what happened since the last poll.
  Input poll();

 private:
  static void on_key(GLFWwindow* w, int key, int scancode, int action, int mods);
  static void on_scroll(GLFWwindow* w, double x, double y);
  static void on_resize(GLFWwindow* w, int width, int height);

  GLFWwindow* window_ = nullptr;
  Input input_;
  double cursor_x_ = 0.0, cursor_y_ = 0.0;
};

}  // namespace aeroflock::render
