#pragma once
// How clipray and an app hand each other GL entry points: a function that returns the address of
// a GL function by name (eglGetProcAddress, glfwGetProcAddress, OSMesaGetProcAddress, or the one
// clipray's headless context gives an app's render function).

namespace clipray {

using GlFunction = void (*)();
using GlGetProcAddress = GlFunction (*)(const char* name);

}  // namespace clipray
