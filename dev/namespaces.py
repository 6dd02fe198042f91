#!/usr/bin/python3
"""Namespaces follow folders (issue 23, layout). Idempotent: run it again on a tree that has
code written against the old namespaces (e.g. after merging another branch).

  coral_introspection::core          -> ::coral (src/coral), ::radar (src/radar),
                                        ::eval (toolbox/src/eval), chosen per name
  coral_introspection::ros_adapters  -> ::ros_eval for the names of toolbox/src/ros_eval;
                                        src/ros keeps ros_adapters (a namespace `ros` inside
                                        coral_introspection would hide roscpp's ::ros)

What it does, in every C++ file of src include toolbox test doc/examples (and the qualified
names in *.md *.yaml *.cfg *.sh *.py):
  1. `namespace core {` / `}  // namespace core` in coral, radar, eval files -> the folder's
     namespace; `namespace ros_adapters {` in ros_eval files -> ros_eval;
  2. `core::Name`, `coral_introspection::core::Name` -> `<folder of Name>::Name` (symbol table
     from universal-ctags over the folders' headers and sources);
     `ros_adapters::Name` / `ra::Name` for a ros_eval name -> `ros_eval::Name`;
  3. `using namespace coral_introspection::core;` -> one using-directive per namespace among
     coral, radar, eval whose headers the file includes (transitively);
     `using namespace coral_introspection::ros_adapters;` gets ros_eval beside it likewise;
  4. `namespace core = coral_introspection::core;` -> aliases of the namespaces the file now
     qualifies with (none if the file has `using namespace coral_introspection;`);
     `namespace ra = ...ros_adapters;` gets `namespace ros_eval = ...` if the file needs it;
  5. in radar, eval and ros_eval files, unqualified uses of another folder's names (legal before
     because coral, radar and eval shared one namespace; ros and ros_eval likewise) are
     qualified: `PointCloud` -> `coral::PointCloud` in radar/eval, `loadNodeConfig` ->
     `ros_adapters::loadNodeConfig` in ros_eval. Declarations (a name after a type) are left.
     Every qualified function name (not a type) is printed as `CHECK`: read those.
Usage: /usr/bin/python3 dev/namespaces.py   (from the repository root)
"""
import os
import re
import subprocess
import sys

ROOT = subprocess.check_output(['git', 'rev-parse', '--show-toplevel'], text=True).strip()
os.chdir(ROOT)

FOLDER_NS = {'coral': 'coral', 'radar': 'radar', 'eval': 'eval', 'ros_eval': 'ros_eval',
             'ros': 'ros_adapters'}
DIRS = {
    'coral': ['include/coral_introspection/coral', 'src/coral'],
    'radar': ['include/coral_introspection/radar', 'src/radar'],
    'eval': ['toolbox/include/coral_introspection/eval', 'toolbox/src/eval'],
    'ros_eval': ['toolbox/include/coral_introspection/ros_eval', 'toolbox/src/ros_eval'],
    'ros': ['include/coral_introspection/ros', 'src/ros'],
}
OLD_NS = {'coral': 'core', 'radar': 'core', 'eval': 'core', 'ros_eval': 'ros_adapters',
          'ros': 'ros_adapters'}
INCLUDE_ROOTS = ['include', 'toolbox/include']
CPP_DIRS = ['src', 'include', 'toolbox', 'test', 'doc/examples']
TEXT_EXT = ('.md', '.yaml', '.cfg', '.sh', '.py', '.txt', '.cmake', '.launch', '.test', '.xml')


def folder_of(path):
    for folder, dirs in DIRS.items():
        for d in dirs:
            if path.startswith(d + '/'):
                return folder
    return None


def symbols():
    """name -> folder, for names declared at namespace scope of each folder."""
    table = {}
    for folder, dirs in DIRS.items():
        dirs = [d for d in dirs if os.path.isdir(d)]
        out = subprocess.check_output(
            ['ctags', '-R', '--languages=C++', '--kinds-C++=+p', '--fields=+sK', '-x',
             '--_xformat=%N\t%K\t%s\t%F'] + dirs, text=True, stderr=subprocess.DEVNULL)
        scopes = {'coral_introspection::' + OLD_NS[folder],
                  'coral_introspection::' + FOLDER_NS[folder]}
        for line in out.splitlines():
            parts = line.split('\t')
            if len(parts) < 4 or parts[2] not in scopes or parts[1] == 'namespace':
                continue
            prev = table.get(parts[0])
            if prev and prev != folder:
                if {prev, folder} == {'ros', 'ros_eval'} or prev in ('coral', 'radar', 'eval'):
                    print('WARNING: %s declared in %s and %s' % (parts[0], prev, folder))
            table.setdefault(parts[0], folder)
    return table


TOKEN = re.compile(r'''
    (?P<comment>//[^\n]*|/\*.*?\*/)
  | (?P<string>R"(?P<delim>[^(\s]*)\(.*?\)(?P=delim)"|"(?:\\.|[^"\\\n])*"|'(?:\\.|[^'\\\n])*')
  | (?P<pp>^[ \t]*\#[^\n]*)
  | (?P<ident>[A-Za-z_]\w*)
  | (?P<punct>::|->|&&|\S)
  | (?P<space>\s+)
''', re.S | re.M | re.X)

KEEP_BEFORE = {'return', 'case', 'else', 'throw', 'new', 'const', 'volatile', 'static',
               'inline', 'constexpr', 'typename', 'co_return', 'sizeof', 'alignof', 'decltype',
               'noexcept', 'template', 'public', 'private', 'protected', 'do', 'mutable',
               'extern', 'friend', 'virtual', 'explicit', 'static_cast', 'const_cast',
               'reinterpret_cast', 'dynamic_cast', 'and', 'or', 'not'}


def tokens(text):
    out = []
    for m in TOKEN.finditer(text):
        kind = m.lastgroup if m.lastgroup != 'delim' else 'string'
        for k in ('comment', 'string', 'pp', 'ident', 'punct', 'space'):
            if m.group(k) is not None:
                kind = k
                break
        out.append((kind, m.group(0), m.start()))
    return out


def qualify_unqualified(path, text, table, own, targets, log):
    """Prefix uses of names of the folders `targets` (not `own`) with their namespace."""
    # names the file defines itself (a lambda `auto fail = ...`, a local function): left alone
    local = set(re.findall(r'\bauto\s+(\w+)\s*=', text))
    local |= set(re.findall(r'\b(?!return\b|else\b|case\b|throw\b|new\b|delete\b)[A-Za-z_][\w:]*'
                            r'(?:<[^;()]*>)?[ \t*&]+(\w+)\s*(?:=[^=]|;|\{)', strip_comments(text)))
    local |= set(re.findall(r'^(?:static\s+|inline\s+)*[\w:<>,]+[\s*&]+(\w+)\s*\([^;]*$',
                            text, re.M))
    toks = tokens(text)
    sig = [i for i, t in enumerate(toks) if t[0] in ('ident', 'punct')]
    edits = []
    for n, i in enumerate(sig):
        kind, val, pos = toks[i]
        if kind != 'ident' or table.get(val) not in targets or val in local:
            continue
        prev = toks[sig[n - 1]][1] if n > 0 else ''
        nxt = toks[sig[n + 1]][1] if n + 1 < len(sig) else ''
        if prev in ('::', '.', '->', '~', 'struct', 'class', 'enum', 'using', 'namespace',
                    'goto'):
            continue
        if nxt == '::' and table.get(val) is None:
            continue
        if re.match(r'[A-Za-z_]', prev) and prev not in KEEP_BEFORE:
            continue  # a declaration: `Type name`
        if prev in ('*', '&', '&&', '>') and nxt == '(' and val[0].isupper():
            pass  # `x * Vec3(...)`: a type constructed in an expression
        elif prev in ('*', '&', '&&', '>') and nxt in (';', '=', ',', ')', '{', '[', '('):
            # `Type* name;` `Type& name(` ... a declaration, or an expression: say so
            log.append('SKIPPED %s:%d: %s%s (after %r): check' % (
                path, text.count('\n', 0, pos) + 1, val, '', prev))
            continue
        ns = FOLDER_NS[table[val]]
        if not val[0].isupper() and not val.startswith('k'):
            log.append('CHECK %s:%d: %s -> %s::%s' % (path, text.count('\n', 0, pos) + 1, val,
                                                     ns, val))
        edits.append((pos, ns + '::'))
    for pos, ins in reversed(edits):
        text = text[:pos] + ins + text[pos:]
    return text


def includes_closure(path, cache={}):
    """Folders (coral, radar, eval, ros, ros_eval) whose headers path includes, transitively."""
    seen, todo, folders = set(), [path], set()
    while todo:
        p = todo.pop()
        if p in seen or not os.path.exists(p):
            continue
        seen.add(p)
        with open(p, encoding='utf-8') as f:
            for inc in re.findall(r'#include\s+[<"](coral_introspection/[^">]+)[">]', f.read()):
                for r in INCLUDE_ROOTS:
                    full = os.path.join(r, inc)
                    if os.path.exists(full):
                        todo.append(full)
                        sub = inc.split('/')[1]
                        if sub in FOLDER_NS:
                            folders.add(sub)
    return folders


def rewrite_cpp(path, text, table, log):
    folder = folder_of(path)
    # 1. own namespace blocks
    if folder in ('coral', 'radar', 'eval'):
        text = re.sub(r'\bnamespace core\b(?!\s*=)', 'namespace ' + folder, text)
    if folder == 'ros_eval':
        text = re.sub(r'\bnamespace ros_adapters\b(?!\s*=)', 'namespace ros_eval', text)
    text = rewrite_qualified(path, text, table, log)
    # 3. using-directives
    closure = includes_closure(path) | ({folder} if folder else set())

    def using_core(m):
        ind = m.group(1)
        nss = [f for f in ('coral', 'radar', 'eval') if f in closure] or ['coral']
        return '\n'.join('%susing namespace coral_introspection::%s;' % (ind, f) for f in nss)
    text = re.sub(r'^([ \t]*)using namespace coral_introspection::core;', using_core, text,
                  flags=re.M)
    if 'ros_eval' in closure and 'using namespace coral_introspection::ros_eval;' not in text:
        text = re.sub(r'^([ \t]*)using namespace coral_introspection::ros_adapters;',
                      r'\g<0>\n\1using namespace coral_introspection::ros_eval;', text,
                      flags=re.M)
    # 4. aliases
    has_using = re.search(r'using namespace coral_introspection;', text) is not None
    body = re.sub(r'^[ \t]*namespace \w+ = coral_introspection::\w+;\n', '', text, flags=re.M)
    used = [f for f in ('coral', 'radar', 'eval', 'ros_eval')
            if re.search(r'(?<![\w:])' + f + r'::', strip_comments(body))]

    def alias_core(m):
        if has_using:
            return ''
        ind = m.group(1)
        out = ''
        for f in ('coral', 'radar', 'eval'):
            if f in used and not re.search(r'namespace %s = ' % f, text):
                out += '%snamespace %s = coral_introspection::%s;\n' % (ind, f, f)
        return out
    text = re.sub(r'^([ \t]*)namespace core = coral_introspection::core;\n', alias_core, text,
                  flags=re.M)
    if 'ros_eval' in used and not has_using and 'namespace ros_eval = ' not in text \
            and folder not in ('ros_eval',) and not re.search(r'^namespace coral_introspection',
                                                              text, re.M):
        if re.search(r'^[ \t]*namespace \w+ = coral_introspection::ros_adapters;', text, re.M):
            text = re.sub(r'^([ \t]*)namespace \w+ = coral_introspection::ros_adapters;\n',
                          r'\g<0>\1namespace ros_eval = coral_introspection::ros_eval;\n', text,
                          count=1, flags=re.M)
        elif not re.search(r'using namespace coral_introspection::ros_eval;', text):
            log.append('ALIAS? %s uses ros_eval:: without alias' % path)
    # an alias of ros_adapters that nothing uses any more (its names were all ros_eval's)
    for alias in re.findall(r'^[ \t]*namespace (\w+) = coral_introspection::ros_adapters;', text,
                            re.M):
        rest = re.sub(r'^[ \t]*namespace \w+ = coral_introspection::\w+;\n', '', text, flags=re.M)
        if not re.search(r'(?<![\w:])' + alias + r'::', strip_comments(rest)):
            text = re.sub(r'^[ \t]*namespace ' + alias + r' = coral_introspection::ros_adapters;\n',
                          '', text, flags=re.M)
    # 5. unqualified cross-folder names
    if folder == 'radar':
        text = qualify_unqualified(path, text, table, folder, {'coral'}, log)
    elif folder == 'eval':
        text = qualify_unqualified(path, text, table, folder, {'coral', 'radar'}, log)
    elif folder == 'ros_eval':
        text = qualify_unqualified(path, text, table, folder, {'ros'}, log)
    return text


def strip_comments(text):
    return re.sub(r'//[^\n]*|/\*.*?\*/', '', text, flags=re.S)


def rewrite_qualified(path, text, table, log):
    def core_name(m):
        full, name = m.group(1) or '', m.group(2)
        f = table.get(name)
        if f not in ('coral', 'radar', 'eval'):
            log.append('UNKNOWN %s: core::%s' % (path, name))
            return m.group(0)
        return '%s%s::%s' % (full, f, name)
    text = re.sub(r'(?<![\w:])(coral_introspection::)?core::(\w+)', core_name, text)

    aliases = set(re.findall(r'namespace (\w+) = coral_introspection::ros_adapters;', text))
    quals = {'ros_adapters'} | aliases

    def ros_name(m):
        full, qual, name = m.group(1) or '', m.group(2), m.group(3)
        if table.get(name) == 'ros_eval':
            if full:
                return 'coral_introspection::ros_eval::' + name
            return 'ros_eval::' + name
        return m.group(0)
    text = re.sub(r'(?<![\w:])(coral_introspection::)?(' + '|'.join(sorted(quals)) +
                  r')::(\w+)', ros_name, text)
    return text


def main():
    table = symbols()
    log = []
    files = subprocess.check_output(['git', 'ls-files'], text=True).split()
    files += subprocess.check_output(['git', 'ls-files', '--others', '--exclude-standard'],
                                     text=True).split()
    for path in sorted(set(files)):
        if path.startswith('dev/') or not os.path.isfile(path):
            continue
        is_cpp = path.endswith(('.cpp', '.hpp', '.h')) and path.split('/')[0] in (
            'src', 'include', 'toolbox', 'test', 'doc')
        if not is_cpp and not path.endswith(TEXT_EXT) and path != '.ci/run':
            continue
        if path.startswith('scripts/ci/check_install.sh'):
            continue  # its symbol regex is edited by hand
        with open(path, encoding='utf-8') as f:
            text = f.read()
        new = rewrite_cpp(path, text, table, log) if is_cpp else \
            rewrite_qualified(path, text, table, log)
        if new != text:
            with open(path, 'w', encoding='utf-8') as f:
                f.write(new)
            print('updated', path)
    for line in log:
        print(line)


if __name__ == '__main__':
    sys.exit(main())
