"""What people read: ``info`` of a file, poses as text, work-range figures, sweep output folders,
and the demo on the bundled examples."""
