# Code that drives the libraries (the command line, the benchmarks): at -O0 when
# FRAMELESS_UNOPTIMIZED_DRIVERS is on. Sanitized optimization is most of a sanitizer build's
# compile time, and these targets spend little of the tests' run time (test executables do
# spend it: at -O0 the ASan suite ran twice as long).
function(frameless_driver target)
  if(FRAMELESS_UNOPTIMIZED_DRIVERS)
    target_compile_options(${target} PRIVATE -O0)
  endif()
endfunction()
