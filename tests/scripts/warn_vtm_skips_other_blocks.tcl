# A .vtm's polydata block is skipped with a warning naming it; its unstructured blocks merge.
# expect: flow_m_0.vtm:7: warning: block "probe" is a PolyData, not an unstructured grid: skipped
volume ../data/series/flow_m_0.vtm
