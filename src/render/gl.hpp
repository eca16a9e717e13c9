#pragma once
/// @file The GL entry points. libOSMesa exports every gl* function itself, so no loader is
/// needed (and glvnd's libGL must not be linked: it would win symbol lookup).

// clang-format off: glext.h needs gl.h's types first.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>
// clang-format on
