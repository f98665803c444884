# SPDX-License-Identifier: GPL-3.0-or-later
# CPack pre-build script (issue 44, D74): a package runs on every x86-64-v3 machine, so what cpack is about
# to package must hold no instruction above that floor — a build made with -DTALKHEAD_MARCH=native, or
# with -march in CMAKE_CXX_FLAGS, is refused here, not found out on a user's laptop as an illegal instruction.
if(NOT CPACK_TALKHEAD_MARCH STREQUAL "x86-64-v3")
  message(FATAL_ERROR "talkhead: this build was configured with TALKHEAD_MARCH='${CPACK_TALKHEAD_MARCH}'; packages are made "
                      "from the portable build only (the default, x86-64-v3)")
endif()
execute_process(COMMAND bash "${CPACK_TALKHEAD_SOURCE_DIR}/scripts/check-isa" "${CPACK_TEMPORARY_DIRECTORY}" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "talkhead: the files to package hold instructions above x86-64-v3 (above); build them with the default TALKHEAD_MARCH")
endif()
