// The precompiled header of the test executables (tests/CMakeLists.txt, lgi_test_pch): this file only gives the
// header's target a source; the header list is in the CMake file.
