#!/usr/bin/python3
"""The built library holds no complex product fused into one multiply-add.

tvid compiles with -ffp-contract=off: a multiply and an add are never fused, so a lane of the
swarm's SIMD code and the scalar code compute the same bits, and the same source gives the same
reports however the build groups and links it. GCC 12's basic-block vectorizer still fuses a
complex product (std::complex, Eigen's FFT) into vfmaddsub/vfmsubadd where it matches the
pattern; which copy of an inline function the linker then kept decided the last bits of the
spectra and the fits. The build turns that vectorizer off for GCC (CMakeLists.txt); this check
fails when such an instruction is back in the library.

Usage: check_no_fused_products.py OBJDUMP LIBRARY
"""
import re
import subprocess
import sys

FUSED_PAIR = re.compile(r"\bvf(?:madd|msub)(?:sub|add)\d{3}p[sd]\b")


def main() -> int:
    objdump, library = sys.argv[1], sys.argv[2]
    text = subprocess.run([objdump, "-d", "--no-show-raw-insn", library], capture_output=True, text=True,
                          check=True).stdout
    found = {}
    function = "?"
    for line in text.splitlines():
        header = re.match(r"^[0-9a-f]+ <(.*)>:$", line)
        if header:
            function = header.group(1)
        elif FUSED_PAIR.search(line):
            found[function] = found.get(function, 0) + 1
    if found:
        print(f"{library}: {sum(found.values())} fused complex products (vfmaddsub/vfmsubadd) in {len(found)} functions:")
        for name, count in sorted(found.items(), key=lambda kv: -kv[1])[:20]:
            print(f"  {count:5d}  {name}")
        return 1
    print(f"{library}: no fused complex products")
    return 0


if __name__ == "__main__":
    sys.exit(main())
