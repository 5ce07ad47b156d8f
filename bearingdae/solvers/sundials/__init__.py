"""Our binding of the SUNDIALS 7 libraries bundled by scikit-sundae (the compiled IDA core).

Stage: solvers. ``library`` finds and checks the libraries, ``prototypes`` declares the C
functions and IDA's flags, ``callbacks`` holds the residual/Jacobian as numba ``cfunc``s,
``session`` runs one IDA integration and frees its memory. The contract-level solver is
:class:`bearingdae.solvers.ida.IDA`.
"""
