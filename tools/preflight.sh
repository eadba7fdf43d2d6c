#!/bin/sh
# Check what `make setup` needs from the system, before it creates the venv or downloads anything.
# Usage: tools/preflight.sh [PYTHON]. Silent when all is there; otherwise one line naming the first
# missing piece and the Debian/Ubuntu package that provides it, and exit 1. CMake is not checked:
# it comes from its PyPI wheel (requirements.lock).
python=${1:-python3}

# fail WHAT [PACKAGE]: say what is missing (and which package provides it) and stop.
fail() {
    echo "make setup: $1${2:+: on Debian/Ubuntu, sudo apt install $2}" >&2
    exit 1
}

# compiles LANGUAGE COMPILER...: succeed if one of the compilers builds an empty program.
compiles() {
    language=$1
    shift
    for compiler in "$@"; do
        echo 'int main(void) { return 0; }' |
            "$compiler" -x "$language" -o /dev/null - >/dev/null 2>&1 && return 0
    done
    return 1
}

command -v "$python" >/dev/null || fail "$python not found (Python 3.11, 3.12 or 3.13)" python3
# The pinned wheels exist for CPython 3.11-3.13 (not 3.10: NumPy 2.4 and others; not 3.14:
# backports.zstd), the ros-jazzy ones for manylinux_2_28_x86_64 only.
set -- $("$python" - 2>/dev/null <<'EOF'
import os, platform, sys, sysconfig
try:
    import ensurepip, venv  # Debian and Ubuntu ship ensurepip in python3.X-venv
    has_venv = 1
except ImportError:
    has_venv = 0
libc, libc_version = platform.libc_ver()
system = '%s-%s-%s%s' % (platform.system(), platform.machine(), libc, libc_version)
wheels_fit = (system.startswith('Linux-x86_64-glibc')
              and tuple(int(part) for part in libc_version.split('.')[:2]) >= (2, 28))
headers = os.path.isfile(os.path.join(sysconfig.get_paths()['include'], 'Python.h'))
print('%s-%d.%d %s %d %d %d' % ((platform.python_implementation(),) + sys.version_info[:2]
                                + (system, wheels_fit, has_venv, headers)))
EOF
)
[ $# -eq 5 ] || fail "$python does not run (see $python -V)"
version=${1#*-}
case $1 in
    CPython-3.1[123]) ;;
    *) fail "$python is ${1%-*} $version; the pinned wheels (requirements.lock) exist for CPython\
 3.11, 3.12 and 3.13 only" \
        'python3.11 python3.11-venv python3.11-dev, then make setup PYTHON=python3.11' ;;
esac
[ "$3" = 1 ] ||
    fail "the pinned ROS Jazzy wheels exist for Linux x86_64 with glibc >= 2.28 only; this is $2"
[ "$4" = 1 ] || fail "$python -m venv cannot install pip (no ensurepip)" "python$version-venv"
[ "$5" = 1 ] || fail "the Python headers (Python.h) for the interface build are missing" \
    "python$version-dev"
compiles c ${CC:-cc gcc clang} ||
    fail "no working C compiler (${CC:-cc, gcc or clang}) for the generated interface code" \
        'gcc (or build-essential)'
compiles c++ ${CXX:-c++ g++ clang++} ||
    fail "no working C++ compiler (${CXX:-c++, g++ or clang++}) for the generated interface code" \
        'g++ (or build-essential)'
