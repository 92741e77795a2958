// tinyobjloader compiled from its header with the fuzzer's instrumentation (the Debian shared
// library is not instrumented).
#define TINYOBJLOADER_IMPLEMENTATION
#include <tiny_obj_loader.h>
