// The object library that compiles the tests' precompiled header (tests/CMakeLists.txt).
