#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
# Lint.Layers: no include runs up the layers of tests/lint/layers.txt. A file under a folder of
# the table may include headers owned by that folder or by one above it; an include owned by a
# folder below it is refused, naming file, line, header and both folders. Every top-level folder
# that holds C++ code must be in the table (or be tests/, deploy/ or build output).
# Usage: layers.py SOURCE_DIR | layers.py --self-test
import os
import re
import sys
import tempfile

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
CODE = ('.cpp', '.hpp', '.h', '.c', '.cpp.in')
FREE = {'tests', 'deploy', 'build', 'var', 'node_modules', 'docs'}


def read_table(path):
    order, owners = [], {}
    for line in open(path, encoding='utf-8'):
        line = line.split('#', 1)[0].strip()
        if not line:
            continue
        folder, *prefixes = line.split()
        owners.update({p: folder for p in prefixes})
        order.append(folder)
    return order, owners


def owner_of(header, owners):
    best = None
    for prefix, folder in owners.items():
        if header == prefix or (prefix.endswith('/') and header.startswith(prefix)):
            if best is None or len(prefix) > len(best[0]):
                best = (prefix, folder)
    return best[1] if best else None


def check(root, table):
    order, owners = read_table(table)
    rank = {f: i for i, f in enumerate(order)}
    problems = []
    for top in sorted(os.listdir(root)):
        path = os.path.join(root, top)
        if not os.path.isdir(path) or top.startswith('.') or top in FREE:
            continue
        code = []
        for d, dirs, files in os.walk(path):
            dirs[:] = [x for x in dirs if not x.startswith('.')]
            code += [os.path.join(d, f) for f in files if f.endswith(CODE)]
        if not code:
            continue
        if top not in rank:
            problems.append(f'{top}/: a folder of code that {table} does not place in the layers')
            continue
        for f in sorted(code):
            for n, line in enumerate(open(f, encoding='utf-8', errors='replace'), 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                owner = owner_of(m.group(1), owners)
                if owner is not None and rank[owner] > rank[top]:
                    problems.append(f'{os.path.relpath(f, root)}:{n}: includes "{m.group(1)}" of '
                                    f'{owner}/, which comes after {top}/ in the layers '
                                    f'(tests/lint/layers.txt)')
    return problems


def self_test():
    with tempfile.TemporaryDirectory() as root:
        for folder, text in {'common/include/ncqual/common': '#pragma once\n',
                             'storage/src': '#include "ncqual/common/model.hpp"\n',
                             'common/src': '#include "ncqual/storage/database.hpp"\n'}.items():
            os.makedirs(os.path.join(root, folder))
            open(os.path.join(root, folder, 'x.cpp'), 'w').write(text)
        table = os.path.join(root, 'layers.txt')
        open(table, 'w').write('common ncqual/common/\nstorage ncqual/storage/\n')
        found = check(root, table)
        expected = ('common/src/x.cpp:1: includes "ncqual/storage/database.hpp" of storage/, which '
                    'comes after common/ in the layers')
        if len(found) != 1 or not found[0].startswith(expected):
            print('the checker did not refuse exactly the include that runs up:', found)
            return 1
        os.makedirs(os.path.join(root, 'extra'))
        open(os.path.join(root, 'extra', 'y.cpp'), 'w').write('\n')
        if not any(p.startswith('extra/: a folder of code') for p in check(root, table)):
            print('the checker did not name a folder missing from the table')
            return 1
    print('the layers checker refuses an include that runs up and a folder it does not know')
    return 0


def main():
    if sys.argv[1:] == ['--self-test']:
        return self_test()
    if len(sys.argv) != 2:
        print('usage: layers.py SOURCE_DIR | layers.py --self-test', file=sys.stderr)
        return 2
    root = sys.argv[1]
    problems = check(root, os.path.join(root, 'tests', 'lint', 'layers.txt'))
    for p in problems:
        print(p)
    print(f'layers: {len(problems)} include(s) or folder(s) out of order')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
