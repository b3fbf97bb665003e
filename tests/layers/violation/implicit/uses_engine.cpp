// Not compiled: a fixture of the layer check (ctest layers_check_finds_a_violation),
// in which implicit/ includes the engine, which it may not.
#include "engine/cell_store.h"
