#!/usr/bin/python3
"""Path references after dev/layout_moves.sh (issue 23, layout): rewrites include strings of the
renamed ROS adapter headers and every textual path to a moved file, in all tracked text files.
Idempotent: run it again after merging a branch written against the old layout.
  /usr/bin/python3 dev/layout_refs.py [FILES...]   (default: every tracked file)"""
import re
import subprocess
import sys

CORAL_ONLY = ['check_alignment', 'diagnostics', 'outputs', 'params', 'scan_input',
              'scan_source', 'tf_feed']
SCRIPTS = {
    'ci': ['check_data.sh', 'check_format.sh', 'check_install.sh', 'fuzz.sh',
           'mutation_check.sh', 'test_sanitizers.sh'],
    'bench': ['stream_bench.sh', 'soak_oxford.sh', 'soak_rio.sh', 'soak_rio_monitor.py'],
    'experiments': ['aces_relation_icp.py', 'relative_rule_sweep.py', 'rio_demo_stats.py',
                    'rio_loop_check.py', 'rio_tables.py', 'verdict_report.sh',
                    'rviz_screenshot.sh'],
}
RULES = []
# ros/<name>.{hpp,cpp} -> ros/coral_<name>.{hpp,cpp} (include strings and prose paths)
names = '|'.join(CORAL_ONLY)
RULES.append((re.compile(r'(?<![\w])ros/(' + names + r')\.(hpp|cpp)\b'), r'ros/coral_\1.\2'))
# src/{eval,ros_eval,tools} -> toolbox/src/...; include/coral_introspection/{eval,ros_eval}
RULES.append((re.compile(r'(?<!toolbox/)(?<!CMAKE_CURRENT_SOURCE_DIR\}/)(?<![\w])src/(eval|ros_eval|tools)\b(?!_)'),
              r'toolbox/src/\1'))
RULES.append((re.compile(r'(?<!toolbox/)(?<![\w<"])include/coral_introspection/(eval|ros_eval)\b'),
              r'toolbox/include/coral_introspection/\1'))
for d, files in SCRIPTS.items():
    alt = '|'.join(re.escape(f) for f in files)
    RULES.append((re.compile(r'(?<![\w])scripts/(' + alt + r')\b'), r'scripts/' + d + r'/\1'))

# In the moved scripts: their siblings env.sh and ros_session.sh and the repository root.
SCRIPT_DIR_RULES = [
    (re.compile(r'(dirname "\$\{BASH_SOURCE\[0\]\}"\)/)(env\.sh|ros_session\.sh)'), r'\1../\2'),
    (re.compile(r'(dirname "\$\{BASH_SOURCE\[0\]\}"\)/)\.\.(?=")'), r'\1../..'),
    (re.compile(r'source=(env\.sh|ros_session\.sh)\b'), r'source=../\1'),
]

SKIP_EXT = ('.png', '.pdf', '.bag', '.bz2', '.gz', '.csv')


def main():
    files = sys.argv[1:] or subprocess.check_output(['git', 'ls-files'], text=True).split()
    for path in files:
        if path.endswith(SKIP_EXT) or path.startswith('dev/') or '/corpus/' in path:
            continue
        try:
            with open(path, encoding='utf-8') as f:
                text = f.read()
        except (UnicodeDecodeError, FileNotFoundError, IsADirectoryError):
            continue
        new = text
        for rx, rep in RULES:
            new = rx.sub(rep, new)
        if re.match(r'scripts/(ci|bench|experiments)/', path):  # one folder deeper
            for rx, rep in SCRIPT_DIR_RULES:
                new = rx.sub(rep, new)
        if new != text:
            with open(path, 'w', encoding='utf-8') as f:
                f.write(new)
            print('updated', path)


if __name__ == '__main__':
    main()
