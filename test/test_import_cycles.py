# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
No import cycles between the package's modules, read from the source (the AST).

Every import statement of one of the package's modules is an edge of the module
graph, of one of four kinds:

* ``top``: at module level (also inside a module-level ``try`` or ``if``);
* ``typing``: under ``if TYPE_CHECKING:`` (annotations only);
* ``deferred``: inside a function or method, run on first call;
* ``lazy``: a PEP 562 table (``_HOMES`` of :mod:`friction_joint.experiments`,
  ``_LAZY`` of :mod:`friction_joint`) whose ``__getattr__`` imports a name's
  module on first use.  ``from friction_joint.experiments import EXPERIMENTS``
  is an edge to the name's home (``experiments.runner``), not to the package,
  whose ``__init__`` imports nothing.

Importing ``a.b.c`` runs the ``__init__`` of ``a.b`` first, so an edge to a
module also goes to the packages above it (except the importer's own).

A cycle of ``top`` edges fails at import time in some import orders; it fails
here.  A cycle that needs a ``typing``, ``deferred`` or ``lazy`` edge fails too:
an import moved into a function or under ``TYPE_CHECKING`` to get past a cycle
still ties the two modules to each other (neither can be understood, tested
or moved without the other), and the next module-level import closes it at
import time.  The one exception is a deferred import of an optional or heavy
dependency (matplotlib, Dask, rclpy behind the module), listed in
:data:`HEAVY_DEFERRED` with its reason; none is needed today.
"""
import ast
import collections

from sourcetree import package_modules

#: (importer, imported) -> why this deferred edge may close a cycle (an optional heavy
#: dependency behind the imported module); each must be a deferred edge of the graph
HEAVY_DEFERRED: dict = {}
#: module-level PEP 562 tables: name -> module that defines it
LAZY_TABLES = ('_HOMES', '_LAZY')

Edge = collections.namedtuple('Edge', 'importer target kind line')


def _is_type_checking(test):
    return any(isinstance(n, ast.Name) and n.id == 'TYPE_CHECKING' or
               isinstance(n, ast.Attribute) and n.attr == 'TYPE_CHECKING'
               for n in ast.walk(test))


def _imports(tree):
    """Yield (import node, kind) of every import statement of a module."""
    stack = [(node, 'top') for node in tree.body]
    while stack:
        node, kind = stack.pop()
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node, kind
        elif isinstance(node, ast.If) and kind == 'top' and _is_type_checking(node.test):
            stack += [(n, 'typing') for n in node.body] + [(n, kind) for n in node.orelse]
            continue
        inner = 'deferred' if isinstance(
            node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)) else kind
        stack += [(n, inner) for n in ast.iter_child_nodes(node)]


def _absolute(module, is_package, level, name):
    """Absolute name of a (relative) import of ``module``."""
    if not level:
        return name
    base = module.split('.') if is_package else module.split('.')[:-1]
    base = base[:len(base) - (level - 1)]
    return '.'.join(base + ([name] if name else []))


def _lazy_table(tree):
    """Return the module-level PEP 562 table {name: relative module} of a module, or {}."""
    for node in tree.body:
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Dict) and any(
                isinstance(t, ast.Name) and t.id in LAZY_TABLES for t in node.targets):
            table = ast.literal_eval(node.value)
            return {k: v if v.startswith('.') else '.' + v for k, v in table.items()}
    return {}


def build_graph(modules):
    """
    Return the import edges among ``modules``, a list of (dotted name, path).

    An edge names the module that imports, the one imported, the kind (``top``,
    ``typing``, ``deferred``, ``lazy``) and the line of the import statement.
    """
    paths = dict(modules)
    trees = {}
    for module, path in modules:
        with open(path, encoding='utf-8') as fh:
            trees[module] = ast.parse(fh.read(), filename=path)
    packages = {m for m, p in modules if p.endswith('__init__.py')}
    homes = {pkg: {name: _absolute(pkg, True, len(rel) - len(rel.lstrip('.')), rel.lstrip('.'))
                   for name, rel in _lazy_table(trees[pkg]).items()}
             for pkg in packages}

    def targets(base, names):
        for name in names:
            if f'{base}.{name}' in paths:
                yield f'{base}.{name}'                 # a submodule
            elif name in homes.get(base, {}):
                yield homes[base][name]                # its home in the PEP 562 table
            elif base in paths:
                yield base

    edges = []
    for module in trees:
        is_package = module in packages
        own = {'.'.join(module.split('.')[:i]) for i in range(1, module.count('.') + 2)}
        for node, kind in _imports(trees[module]):
            if isinstance(node, ast.ImportFrom):
                base = _absolute(module, is_package, node.level, node.module)
                found = targets(base, [a.name for a in node.names])
            else:
                found = [a.name for a in node.names if a.name in paths]
            for target in found:
                parts = target.split('.')
                for i in range(1, len(parts) + 1):     # the packages above it run first
                    name = '.'.join(parts[:i])
                    if name in paths and name not in own:
                        edges.append(Edge(module, name, kind, node.lineno))
        for target in sorted(set(homes.get(module, {}).values())):
            if target in paths:
                edges.append(Edge(module, target, 'lazy', 0))
    return edges


def _components(nodes, succ):
    """Strongly connected components (Tarjan) with more than one module or a self-import."""
    index, low, on_stack, stack, out = {}, {}, set(), [], []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in succ.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1 or v in succ.get(v, ()):
                out.append(sorted(comp))

    for v in sorted(nodes):
        if v not in index:
            visit(v)
    return out


def _shortest_cycle(comp, succ):
    """Return a shortest cycle (list of modules, the first repeated last) within ``comp``."""
    best = None
    for start in sorted(comp):
        prev, queue = {start: None}, collections.deque([start])
        while queue:
            v = queue.popleft()
            if start in succ.get(v, ()):
                path = [v]
                while prev[path[-1]] is not None:
                    path.append(prev[path[-1]])
                if best is None or len(path) + 1 < len(best):
                    best = path[::-1] + [start]
                break
            for w in sorted(succ.get(v, ())):
                if w in comp and w not in prev:
                    prev[w] = v
                    queue.append(w)
    return best


def find_cycles(edges, kinds):
    """
    Return one line per import cycle among ``edges`` of ``kinds``, naming it edge by edge.

    One line per strongly connected group of modules, showing a shortest cycle in it.
    """
    succ, label = collections.defaultdict(set), {}
    for e in edges:
        if e.kind in kinds and (e.importer, e.target) not in HEAVY_DEFERRED:
            succ[e.importer].add(e.target)
            label.setdefault((e.importer, e.target), f'{e.kind} import, line {e.line}')
    nodes = set(succ) | {t for ts in succ.values() for t in ts}
    lines = []
    for comp in _components(nodes, succ):
        cycle = _shortest_cycle(set(comp), succ)
        pairs = zip(cycle, cycle[1:], strict=False)        # each module and the next
        steps = ' -> '.join(f'{a} ({label[a, b]})' for a, b in pairs)
        lines.append(f'{steps} -> {cycle[0]}   [group: {", ".join(comp)}]')
    return lines


EDGES = build_graph(package_modules())


def test_no_cycle_of_module_level_imports():
    cycles = find_cycles(EDGES, {'top'})
    assert not cycles, 'import cycle at module level:\n' + '\n'.join(cycles)


def test_no_cycle_through_deferred_typing_or_lazy_imports():
    cycles = find_cycles(EDGES, {'top', 'typing', 'deferred', 'lazy'})
    assert not cycles, ('import cycle (an import inside a function, under TYPE_CHECKING or '
                        'through a PEP 562 table still ties the modules together):\n'
                        + '\n'.join(cycles))


def test_heavy_deferred_exceptions_are_deferred_edges():
    deferred = {(e.importer, e.target) for e in EDGES if e.kind == 'deferred'}
    stale = [f'{a} -> {b}: {why}' for (a, b), why in HEAVY_DEFERRED.items()
             if (a, b) not in deferred]
    assert not stale, 'HEAVY_DEFERRED lists edges that are no deferred imports:\n' + \
        '\n'.join(stale)


def test_the_graph_sees_every_kind_of_import():
    """Module-level, deferred, TYPE_CHECKING and PEP 562 imports are all edges."""
    kinds = {(e.importer, e.target): e.kind for e in EDGES}
    assert kinds['friction_joint.gear.files', 'friction_joint.gear.params'] == 'top'
    assert kinds['friction_joint.experiments', 'friction_joint.experiments.runner'] == 'lazy'
    assert kinds['friction_joint', 'friction_joint.models'] == 'lazy'
    assert kinds['friction_joint.jobs', 'friction_joint.jobs.demo'] == 'deferred'
    assert 'typing' in kinds.values()
    # a name of the lazy table is an edge to its home, never to the empty package
    importers = {e.importer for e in EDGES if e.target == 'friction_joint.experiments.runner'}
    assert 'friction_joint.jobs.experiment' in importers or len(importers) > 1


def test_a_cycle_is_found_and_named(tmp_path):
    """The check can fail: a deferred import back into a module's importer is a cycle."""
    pkg = tmp_path / 'pkg'
    pkg.mkdir()
    (pkg / '__init__.py').write_text('')
    (pkg / 'low.py').write_text('def f():\n    from .high import g\n    return g\n')
    (pkg / 'high.py').write_text('from .low import f\n\ng = f\n')
    (pkg / 'lone.py').write_text('import pkg.low\n')
    modules = [(f'pkg.{n}' if n != '__init__' else 'pkg', str(pkg / f'{n}.py'))
               for n in ('__init__', 'low', 'high', 'lone')]
    edges = build_graph(modules)
    assert find_cycles(edges, {'top'}) == []
    cycles = find_cycles(edges, {'top', 'deferred'})
    assert len(cycles) == 1
    assert 'pkg.high (top import, line 1) -> pkg.low (deferred import, line 2)' in cycles[0]
