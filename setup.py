"""Map the repository's top-level folders into the single ``metro`` namespace.

``core/`` -> ``metro.core``, ``plugins/`` -> ``metro.plugins``, ``instruments/`` ->
``metro.instruments``.  The package list is computed, so a new ``plugins/<std>/`` folder
is picked up by both the wheel and the editable install (see shared design notes).
"""

from setuptools import find_namespace_packages, setup

ROOTS = {"core": "metro.core", "plugins": "metro.plugins", "instruments": "metro.instruments"}

package_dir = {}
packages = []
for folder, name in ROOTS.items():
    package_dir[name] = folder
    packages.append(name)
    for sub in find_namespace_packages(where=folder, exclude=["*__pycache__*", "_metro"]):
        packages.append(f"{name}.{sub}")
        package_dir[f"{name}.{sub}"] = f"{folder}/{sub.replace('.', '/')}"

# ``python -m metro``: core/_metro/ holds only ``__main__.py`` and is mapped onto the ``metro``
# namespace itself (no ``__init__.py``, so ``metro`` stays a namespace package).
package_dir["metro"] = "core/_metro"
packages.append("metro")

setup(package_dir=package_dir, packages=packages)
