"""Models: the equations of the papers as closed forms and solves (TV-LIPM, stiffness, VHIP, sextic,
tridiagonal, 3D-SLIP), pure numpy/scipy (docs/architecture.md)."""
