"""Campaign tooling: carrying runs from one machine to the next and
keeping their reduced records (silo3d_carry, silo3d_archive,
silo2d_archive), resuming an interrupted run from its checkpoint
(checkpoint), and where a rotating-silo campaign stands (silo3d_status)."""
