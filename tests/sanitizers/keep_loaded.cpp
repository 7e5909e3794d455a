// LD_PRELOAD'ed by the asan test preset: dlclose() does nothing, so that the Vulkan driver and
// layers that the loader unloads at vkDestroyInstance stay mapped until LeakSanitizer's check at
// exit. Unloaded, the pointers they still hold in their globals are lost (lavapipe's reported as
// leaks) and their frames have no module name for tests/sanitizers/lsan.supp to match.
extern "C" int dlclose(void*) { return 0; }
