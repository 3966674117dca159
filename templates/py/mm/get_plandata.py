{% extends "py/mm/method.py" %}
{%- block body %}
        pos_num, vispos_num = 0, 0
        if {{ m.bad }}:
            status = self.BAD_ARGUMENT
        else:
            # One waypoint per reply, until the server reports all sent (at most {{ v.point_cap }}).
            # Reply: echo, status, all sent, waypoint type (1 = Vision Move), 6 values, motion
            # type, tool, speed, [Vision Move data (formats 3/4, Vision Move waypoints only)],
            # [n, n custom values].
            points = []
            more = True
            while more:
                status, f = self._exchange({{ m.cmd }}, [{{ m.tx }}])
                more = False
                if status != {{ m.ok }}:
                    break
                if len(f) < {{ m.lay.fixed }}:
                    status = self.BAD_REPLY
                    break
                has_plan = jps_pos >= 3 and f[{{ m.lay.wtype_at }}] == 1
                idx = {{ m.lay.fixed }} + ({{ v.plan_results_len }} if has_plan else 0)
                if len(f) < idx:
                    status = self.BAD_REPLY
                    break
                n = 0
                if len(f) > idx:
                    n = int(f[idx])
                    if n < 0 or len(f) != idx + 1 + n:
                        status = self.BAD_REPLY
                        break
                if n > {{ v.user_data_len }} or len(points) >= {{ v.point_cap }}:
                    status = self.TOO_MANY_POINTS
                    break
                p = _MMPoint(f[{{ m.lay.head }} : {{ m.lay.head + 6 }}], 0, f[{{ m.lay.speed_at }}])
                p.vision_move = int(f[{{ m.lay.wtype_at }}])
                p.move_type = int(f[{{ m.lay.move_at }}])
                p.tool = int(f[{{ m.lay.tool_at }}])
                p.plan = f[{{ m.lay.fixed }} : {{ m.lay.fixed + v.plan_results_len }}] if has_plan else None
                p.user_data = f[idx + 1 : idx + 1 + n]
                points.append(p)
                if vispos_num == 0 and p.vision_move == 1:
                    vispos_num = len(points)
                more = f[{{ m.lay.all_sent_at }}] == 0
            if status == {{ m.ok }}:
                self._points, self._kind, self._pt_status = points, self.KIND_PLAN, status
                self._plan_jps_pos = jps_pos
                pos_num = len(points)
            else:
                vispos_num = 0
                if points:
                    # KUKA's storage was partly overwritten: nothing valid is left.
                    self._points, self._kind = [], 0
        self.last_status = status
        return {{ m.ret }}
{%- endblock %}
