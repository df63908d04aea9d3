# Cross build for Linux aarch64 with Debian's g++-aarch64-linux-gnu; the tests run under
# qemu-user (`make test-cross`).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH /usr/aarch64-linux-gnu)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# GLM is header-only, so the host's headers serve, seen through a folder of their own: adding
# /usr/include itself would put the host's C library headers before the target's.
file(MAKE_DIRECTORY ${CMAKE_BINARY_DIR}/glm-include)
file(CREATE_LINK /usr/include/glm ${CMAKE_BINARY_DIR}/glm-include/glm SYMBOLIC)
set(GLM_INCLUDE_DIR ${CMAKE_BINARY_DIR}/glm-include CACHE PATH "GLM headers")
