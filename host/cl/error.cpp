// Names for OpenCL error codes and the throwing helper behind LGN_CL_CHECK.
#include "host/cl/error.h"

#include <fmt/format.h>

namespace lorgnette::cl {

const char* error_name(cl_int code) {
  switch (code) {
#define LGN_CASE(x) \
  case x:           \
    return #x;
    LGN_CASE(CL_SUCCESS)
    LGN_CASE(CL_DEVICE_NOT_FOUND)
    LGN_CASE(CL_DEVICE_NOT_AVAILABLE)
    LGN_CASE(CL_COMPILER_NOT_AVAILABLE)
    LGN_CASE(CL_MEM_OBJECT_ALLOCATION_FAILURE)
    LGN_CASE(CL_OUT_OF_RESOURCES)
    LGN_CASE(CL_OUT_OF_HOST_MEMORY)
    LGN_CASE(CL_BUILD_PROGRAM_FAILURE)
    LGN_CASE(CL_INVALID_VALUE)
    LGN_CASE(CL_INVALID_DEVICE)
    LGN_CASE(CL_INVALID_CONTEXT)
    LGN_CASE(CL_INVALID_COMMAND_QUEUE)
    LGN_CASE(CL_INVALID_MEM_OBJECT)
    LGN_CASE(CL_INVALID_BINARY)
    LGN_CASE(CL_INVALID_BUILD_OPTIONS)
    LGN_CASE(CL_INVALID_PROGRAM)
    LGN_CASE(CL_INVALID_PROGRAM_EXECUTABLE)
    LGN_CASE(CL_INVALID_KERNEL_NAME)
    LGN_CASE(CL_INVALID_KERNEL)
    LGN_CASE(CL_INVALID_ARG_INDEX)
    LGN_CASE(CL_INVALID_ARG_VALUE)
    LGN_CASE(CL_INVALID_ARG_SIZE)
    LGN_CASE(CL_INVALID_KERNEL_ARGS)
    LGN_CASE(CL_INVALID_WORK_DIMENSION)
    LGN_CASE(CL_INVALID_WORK_GROUP_SIZE)
    LGN_CASE(CL_INVALID_WORK_ITEM_SIZE)
    LGN_CASE(CL_INVALID_GLOBAL_OFFSET)
    LGN_CASE(CL_INVALID_EVENT_WAIT_LIST)
    LGN_CASE(CL_INVALID_OPERATION)
    LGN_CASE(CL_INVALID_BUFFER_SIZE)
    LGN_CASE(CL_INVALID_GLOBAL_WORK_SIZE)
    LGN_CASE(CL_INVALID_PLATFORM)
#undef LGN_CASE
    case -1001:
      return "CL_PLATFORM_NOT_FOUND_KHR";
    default:
      return "CL_UNKNOWN_ERROR";
  }
}

void throw_error(cl_int code, const char* call, const char* file, int line) {
  throw Error(fmt::format("OpenCL call failed: {} returned {} ({}) at {}:{}", call, error_name(code), code,
                          file, line),
              code);
}

}  // namespace lorgnette::cl
