"""Reports that run a study, draw its figures and write numbers and text: the main job on a preset,
the chapter-4 and chapter-6 studies, the analysis of a record and the thesis reproduction."""
