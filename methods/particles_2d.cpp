/// 2D particle sets: rectangle lattices, Voronoi volumes (voro++), stress points (001 eq 65).
#include "methods/particles.hpp"
