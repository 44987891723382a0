# Sourced by scripts/sanitize.sh and scripts/fuzz.sh: every sanitizer report is fatal.
# (ASan always stops at its first error; halt_on_error makes UBSan do the same at run time, on
# top of -fno-sanitize-recover=all at compile time.) Leaks are checked, except OpenCascade's
# one-time registrations listed with their reasons in scripts/lsan.supp.
_isospring_scripts="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1${ASAN_OPTIONS:+:$ASAN_OPTIONS}"
export LSAN_OPTIONS="suppressions=$_isospring_scripts/lsan.supp:print_suppressions=0${LSAN_OPTIONS:+:$LSAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
unset _isospring_scripts
