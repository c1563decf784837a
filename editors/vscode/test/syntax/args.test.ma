# SYNTAX TEST "source.slocum_ma" "Slocum mission arguments: behavior_name, b_arg sections, waypoints, comments"
behavior_name=Goto_list
# <------------- keyword.other.behavior-name.slocum_ma
#            ^ keyword.operator.assignment.slocum_ma
#             ^^^^^^^^^ entity.name.function.behavior.slocum_ma
<start:b_arg>
# <- punctuation.definition.tag.begin.slocum_ma
#^^^^ keyword.control.section.slocum_ma
#      ^^^^^ entity.name.section.slocum_ma
	b_arg: list_when_wpt_dist(m) 500
#^^^^^^ keyword.other.b-arg.slocum_ma
#       ^^^^^^^^^^^^^^^^^^ variable.parameter.argument.slocum_ma
#                          ^ support.type.units.slocum_ma
#                             ^^^ constant.numeric.slocum_ma
<end:b_arg>
# <- punctuation.definition.tag.begin.slocum_ma
#^^^ keyword.control.section.slocum_ma
<start:waypoints>
713.000 5433.500
# <------- constant.numeric.longitude.slocum_ma
#       ^^^^^^^^ constant.numeric.latitude.slocum_ma
#729.430  5414.300
# <------------------ comment.line.number-sign.slocum_ma
<end:waypoints>
