// tinygltf's implementation, compiled into the fuzz targets with their instrumentation in place of
// Debian's libtinygltf (built from this same header): the fuzzer then sees tinygltf's branches and
// the sanitizers check its memory accesses. Images still decode in libstb, uninstrumented.
#define TINYGLTF_IMPLEMENTATION
#include <tiny_gltf.h>
