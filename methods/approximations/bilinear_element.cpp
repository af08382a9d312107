/// Bilinear (Q4) element shape functions on a 2D particle lattice (the FEM reference).
#include "methods/approximations/approximation.hpp"
