# The stages of vantage, bottom up, and what each may use (docs/architecture.md). Read by
# CMakeLists.txt (one library target per stage, linked in this order) and by CheckLayering.cmake,
# which fails the configure step and the `layering` test when a file includes a header of a stage
# it may not use.
set(VANTAGE_STAGES util scene reference candidates visibility observe select assess report render
    pipeline distribute)

# Public headers (include/vantage/<name>.hpp) by owning stage.
set(VANTAGE_HEADERS_util types error rng sensors settings scene_settings interrupt words output_guard)
set(VANTAGE_HEADERS_scene scene population scene_states robot problem mesh_weld)
set(VANTAGE_HEADERS_reference reference)
set(VANTAGE_HEADERS_candidates candidates arm)
set(VANTAGE_HEADERS_visibility visibility visibility_file)
set(VANTAGE_HEADERS_observe observe ray_scene)
set(VANTAGE_HEADERS_select select select_states selection_options constraints tour track)
set(VANTAGE_HEADERS_assess refine robustness pose_tolerance)
set(VANTAGE_HEADERS_report report visualize yaml_export gazebo_export)
set(VANTAGE_HEADERS_render render)
set(VANTAGE_HEADERS_pipeline pipeline external_matrix)
set(VANTAGE_HEADERS_distribute distribute)

# Stages each stage may include (itself included). Selection sees only the matrix header of the
# visibility stage (VANTAGE_EXTRA_select): no scene, no candidate geometry, no Embree.
set(VANTAGE_USES_util util)
set(VANTAGE_USES_scene util scene)
set(VANTAGE_USES_reference util scene reference)
set(VANTAGE_USES_candidates util scene candidates)
set(VANTAGE_USES_visibility util scene reference candidates visibility)
set(VANTAGE_USES_observe util scene reference candidates visibility observe)
set(VANTAGE_USES_select util select)
set(VANTAGE_EXTRA_select visibility)
set(VANTAGE_USES_assess util scene reference candidates visibility observe select assess)
set(VANTAGE_USES_report util scene reference candidates visibility observe select assess report)
set(VANTAGE_USES_render ${VANTAGE_USES_report} render)
set(VANTAGE_USES_pipeline ${VANTAGE_USES_render} pipeline)
# The distribution layer sits on the pipeline: its TraceFunction, ObserveForOptimize/FinishOptimize.
set(VANTAGE_USES_distribute ${VANTAGE_USES_pipeline} distribute)

# Third-party headers (the first path component of <...>) that only these stages may include.
set(VANTAGE_ONLY_embree3 observe)
set(VANTAGE_ONLY_coin select)
set(VANTAGE_ONLY_nauty.h select)
set(VANTAGE_ONLY_nausparse.h select)
set(VANTAGE_ONLY_assimp scene)
set(VANTAGE_ONLY_urdf_parser scene)
set(VANTAGE_ONLY_console_bridge scene)
set(VANTAGE_ONLY_CLI "")
set(VANTAGE_ONLY_mpi.h distribute)
# A camera on a robot arm (issue 45): kinematics (Orocos KDL), collisions (FCL), planning (OMPL).
set(VANTAGE_ONLY_kdl candidates)
set(VANTAGE_ONLY_fcl candidates)
set(VANTAGE_ONLY_ompl candidates)

# Headers generated into the build tree, by the stage that includes them (cmake/EmbedFiles.cmake).
set(VANTAGE_GENERATED_embedded report)
