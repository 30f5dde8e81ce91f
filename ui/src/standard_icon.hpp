#pragma once
// The style's standard icons, one of each for the whole process: a model that returns a fresh
// QStyle::standardIcon() for every row has its image decoded again at every paint (expanding a
// thousand-part scene tree took 0.3 s that way, 17 ms with the icon shared).
#include <QApplication>
#include <QIcon>
#include <QStyle>
#include <map>
#include <utility>

namespace vaw::ui {

inline QIcon standardIcon(QStyle::StandardPixmap which) {
  const QStyle* style = QApplication::style();
  if (style == nullptr) return {};
  static std::map<std::pair<const QStyle*, QStyle::StandardPixmap>, QIcon> icons;
  auto it = icons.find({style, which});
  if (it == icons.end()) it = icons.emplace(std::pair{style, which}, style->standardIcon(which)).first;
  return it->second;
}

}  // namespace vaw::ui
