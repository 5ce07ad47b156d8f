# The kernels of this folder are cached by the hash of the package's source contents, in a
# folder of that hash (util/kernel_cache.py): set up before any kernel module is decorated.
from ..util.kernel_cache import install as _install_kernel_cache  # noqa: E402

_install_kernel_cache()
