"""The workbench's document objects: the proxies of its parametric features, which recompute through
the kernel (st_bridge). Data only: no view providers or GUI code here (stviewproviders has those)."""
