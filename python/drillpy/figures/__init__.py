"""Every figure, one module per area (Agg backend: files only). Figures take the result objects
that the compute functions return; none of them computes a study."""
