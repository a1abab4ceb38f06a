# cmake/check_variant_symbols.cmake -- fails unless every code symbol that a kernel variant's
# object files define with external linkage carries the variant's namespace in its name.
#
# Why: the linker keeps one copy of each inline function (a weak symbol), from whichever object
# comes first. Were the AVX2 variant's copy of a function the baseline also uses kept, the
# baseline's callers would run AVX2 code, and crash on a CPU without it. The variant
# (src/kernel/entry_points.hpp) defines everything in tetia::detail::<variant> or with internal
# linkage; this check keeps it so.
#
# Usage: cmake -DNM=<nm> -DNAMESPACE=<variant namespace> -DOBJECTS=<o1;o2...> -P this file
foreach(var NM NAMESPACE OBJECTS)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "check_variant_symbols: ${var} not given")
  endif()
endforeach()
string(LENGTH "${NAMESPACE}" ns_length)
set(mangled "${ns_length}${NAMESPACE}")  # how the Itanium ABI spells the namespace in a name
set(offenders "")
set(defined 0)
foreach(object ${OBJECTS})
  execute_process(COMMAND ${NM} --defined-only --extern-only ${object}
    OUTPUT_VARIABLE listing ERROR_VARIABLE errors RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "check_variant_symbols: ${NM} failed on ${object}: ${errors}")
  endif()
  string(REPLACE "\n" ";" lines "${listing}")
  foreach(line ${lines})
    # "<address> <type> <name>"; code: T (text), W (weak, object or code), i (indirect function).
    if(line MATCHES "^[0-9a-fA-F]* *([A-Za-z]) (.+)$")
      set(type "${CMAKE_MATCH_1}")
      set(name "${CMAKE_MATCH_2}")
      math(EXPR defined "${defined} + 1")
      if(type MATCHES "^[TWi]$")
        string(FIND "${name}" "${mangled}" at)
        if(at EQUAL -1)
          string(APPEND offenders "\n  ${type} ${name}")
        endif()
      endif()
    endif()
  endforeach()
endforeach()
if(defined EQUAL 0)
  message(FATAL_ERROR "check_variant_symbols: ${OBJECTS} define no symbol (not the variant's objects?)")
endif()
if(NOT offenders STREQUAL "")
  message(FATAL_ERROR "check_variant_symbols: the ${NAMESPACE} kernel variant defines code the "
    "linker could bind baseline callers to (names outside its namespace; make them internal or "
    "templated on the variant, src/kernel/entry_points.hpp; an unoptimized build emits even std::min "
    "out of line: configure it with -DTETIA_KERNEL_VARIANTS=OFF):${offenders}")
endif()
