// Compiles the tests' precompiled headers (target sb_test_headers in CMakeLists.txt); the test
// binaries reuse them. Nothing of its own.
