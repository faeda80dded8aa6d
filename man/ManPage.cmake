# Writes the man page of one octarc command from what the command itself prints: its usage
# (-h) and its configuration keys with their defaults and descriptions (-dd), the tables -h and
# -d are printed from. Run by the build (cmake -P):
#   -DOCTARC=<octarc executable> -DOCTARC_COMMAND="simulate lenses" -DVERSION=0.1.0
#   -DOUTPUT=<page.1>
# OCTARC_COMMAND empty: the page of octarc itself (octarc -h).
cmake_minimum_required(VERSION 3.18)

# roff text: a backslash written \e, a line starting with . or ' protected with \&.
function(roff_escape text out)
  string(REPLACE "\\" "\\e" text "${text}")
  string(REGEX REPLACE "(^|\n)([.'])" "\\1\\\\&\\2" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

function(run_octarc out)
  separate_arguments(words UNIX_COMMAND "${OCTARC_COMMAND}")
  execute_process(COMMAND ${OCTARC} ${words} ${ARGN} OUTPUT_VARIABLE text
                  RESULT_VARIABLE status ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "octarc ${OCTARC_COMMAND} ${ARGN}: exit ${status}: ${err}")
  endif()
  set(${out} "${text}" PARENT_SCOPE)
endfunction()

if(OCTARC_COMMAND STREQUAL "")
  set(page_name "octarc")
else()
  string(REPLACE " " "-" page_name "octarc-${OCTARC_COMMAND}")
endif()
string(TOUPPER "${page_name}" title)

# The one-line summary: the command's description in `octarc -h`'s list of commands (the
# indented lines after "  <command> ...").
set(summary "find lenses by the octopole arcness of their arcs")
if(NOT OCTARC_COMMAND STREQUAL "")
  set(saved_command "${OCTARC_COMMAND}")
  set(OCTARC_COMMAND "")
  run_octarc(overview -h)
  set(OCTARC_COMMAND "${saved_command}")
  string(REPLACE ";" "," overview "${overview}")
  string(REPLACE "\n" ";" lines "${overview}")
  set(summary "")
  set(inside FALSE)
  foreach(line IN LISTS lines)
    if(line MATCHES "^  ${OCTARC_COMMAND}( |$)")
      set(inside TRUE)
    elseif(inside AND line MATCHES "^      +(.*)$")
      string(APPEND summary " ${CMAKE_MATCH_1}")
    elseif(inside)
      break()
    endif()
  endforeach()
  string(STRIP "${summary}" summary)
  if(summary STREQUAL "")
    message(FATAL_ERROR "octarc -h does not describe the command ${OCTARC_COMMAND}")
  endif()
endif()
roff_escape("${summary}" summary)
string(TIMESTAMP date "%Y-%m-%d" UTC)  # SOURCE_DATE_EPOCH when set

run_octarc(usage -h)
roff_escape("${usage}" usage)
set(page ".TH ${title} 1 ${date} \"octarc ${VERSION}\" \"octarc manual\"\n")
string(APPEND page ".SH NAME\n${page_name} \\- ${summary}\n")
string(APPEND page ".SH DESCRIPTION\n.nf\n${usage}.fi\n")
if(NOT OCTARC_COMMAND STREQUAL "")
  run_octarc(keys -dd)
  roff_escape("${keys}" keys)
  string(APPEND page ".SH CONFIGURATION KEYS\n"
         "Every key, as \\fBoctarc ${OCTARC_COMMAND} \\-dd\\fR prints it\n"
         "(a .sex file: KEY, its default, what it is);\n"
         "\\fB\\-KEY value\\fR on the command line overrides it.\n"
         ".PP\n.nf\n${keys}.fi\n")
  string(APPEND page ".SH SEE ALSO\n\\fBoctarc\\fR(1), the README in /usr/share/doc/octarc\n")
else()
  string(APPEND page ".SH SEE ALSO\n\\fBoctarc\\-detect\\fR(1) and the page of every command,\n"
         "the README in /usr/share/doc/octarc\n")
endif()
file(WRITE "${OUTPUT}" "${page}")
