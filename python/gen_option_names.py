"""Writes ellipsekit/_option_names.py: the field names of struct Options in include/ellipsekit/options.h,
in declaration order (run by the build whenever the header changes; python/CMakeLists.txt).

    python3 gen_option_names.py include/ellipsekit/options.h OUT.py

The names are for help() and completion only: parsing and checking stay the C++ library's
(ellipsekit::SetOption, ValidateOptions), and python/tests/test_api.py checks that the parser knows
every name listed here.
"""
import re
import sys


def option_names(header_text):
    body = header_text[header_text.index("struct Options {"):]
    body = body[:body.index("\n};")]
    return re.findall(r"^\s+[\w:<>]+\s+(\w+)\s*(?:=[^;]*)?;", body, flags=re.M)


def main():
    header, out = sys.argv[1], sys.argv[2]
    names = option_names(open(header, encoding="utf-8").read())
    if len(names) < 10:
        sys.exit(f"gen_option_names.py: found only {names} in {header}")
    text = ("# Generated from include/ellipsekit/options.h by python/gen_option_names.py; do not edit.\n"
            "OPTION_NAMES = (\n" + "".join(f"    {n!r},\n" for n in names) + ")\n")
    with open(out, "w", encoding="utf-8") as f:
        f.write(text)


if __name__ == "__main__":
    main()
