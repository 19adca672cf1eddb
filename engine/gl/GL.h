#pragma once
// The one place GL headers are included, so that GLEW always comes first.
#include <GL/glew.h>
